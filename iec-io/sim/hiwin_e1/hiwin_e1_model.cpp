#include "hiwin_e1/hiwin_e1_model.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "plc/fb/drive/scaling.hpp"

namespace plc::sim {

using namespace plc::drive;

namespace {
constexpr std::uint16_t kOk = 0xFFFF;  // "no error" for the element accessors
constexpr std::uint16_t kWarnOvertravel = 0x09A0;
constexpr std::uint16_t kFaultSignOfLife = 0xFB1;      // AL.FB1, no. 73
constexpr std::uint16_t kFaultFollowingError = 0xD00;  // AL.d00, no. 62

// The drive's sign-of-life after a step, by [frozen][now]: the same value
// when frozen, else next_sign_of_life(). sol_ is 0 (restart) or a
// next_sign_of_life() (1..15), so it indexes the table; a look-up instead
// of the branches of the freeze and the wrap in the rest repeat.
constexpr auto kSolAfterStep = [] {
  std::array<std::array<std::uint8_t, 16>, 2> t{};
  for (std::uint8_t v = 0; v < 16; ++v) {
    t[0][v] = next_sign_of_life(v);
    t[1][v] = v;
  }
  return t;
}();

// STW1 and POS_STW2 of telegram 111 as their decoded flags' word() would
// rebuild them: the defined bits of the PLC's words. Taken from the bytes
// every step instead of reassembling twelve flags (decode_111 keeps the
// flags for the rest); the asserts hold the shortcut to the flag mapping.
template <class W>
consteval bool word_is_defined_bits() {
  for (unsigned w = 0; w <= 0xFFFF; w += 0x0101)
    if (W::from(static_cast<std::uint16_t>(w)).word() != (w & W::kDefined)) return false;
  for (unsigned b = 0; b < 16; ++b) {
    const auto w = static_cast<std::uint16_t>(1u << b);
    if (W::from(w).word() != (w & W::kDefined)) return false;
  }
  return true;
}
static_assert(word_is_defined_bits<Stw1Pos>());
static_assert(word_is_defined_bits<PosStw2>());

// PNUs used by the model (spec §6.1-§6.3).
constexpr std::uint16_t kPnuTelegram = 922, kPnuSolTolerance = 925, kPnuOpMode = 930,
                        kPnuFaultMsgCounter = 944, kPnuFaultCode = 945, kPnuFaultNumber = 947,
                        kPnuFaultScaling = 950, kPnuFaultSituations = 952, kPnuDriveId = 964,
                        kPnuEncoderFormat = 979;
constexpr std::uint16_t kPt001 = pt_pnu(0x001), kPt30A = pt_pnu(0x30A), kPt316 = pt_pnu(0x316),
                        kPt317 = pt_pnu(0x317), kPt385 = pt_pnu(0x385), kPt386 = pt_pnu(0x386),
                        kPt402 = pt_pnu(0x402), kPt403 = pt_pnu(0x403), kPt483 = pt_pnu(0x483),
                        kPt484 = pt_pnu(0x484), kPt533 = pt_pnu(0x533), kPt534 = pt_pnu(0x534),
                        kPt537 = pt_pnu(0x537), kPt538 = pt_pnu(0x538), kPt53A = pt_pnu(0x53A),
                        kPt585 = pt_pnu(0x585);
constexpr std::uint16_t kAbsInit = 0x3200, kResetDrive = 0x3215, kSaveFlash = 0x3216,
                        kGantryMode = 0x3057, kOvertravelStopMode = 0x3062;

double sgn(double v) { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); }

// Ranges: positions and windows are in control units (CU); the telegrams
// carry positions as DINT, so windows stop at 2^31 - 1, while encoder
// positions (multi-turn counts) may go to +-1e18 CU (the default "no limit"),
// which keeps turns = position / cu_per_rev inside an int64. Speeds to
// 100,000 rpm, times to an hour: beyond any servo, still finite.
HiwinE1Config config_from(const io::ModelParams& p) {
  HiwinE1Config c;
  const auto tg = p.get_int("telegram", 111, 0, 65535);
  if (!is_supported_telegram(static_cast<unsigned>(tg)))
    throw io::ParamError("telegram",
                         "telegram must be 3, 9 or 111 (spec §1.2), got " + std::to_string(tg));
  c.telegram = static_cast<TelegramType>(tg);
  constexpr double kDint = 2147483647.0, kPos = 1e18, kRpm = 100000, kMs = 3600000;
  c.cu_per_rev = p.get_double("cu_per_rev", c.cu_per_rev, 1, kDint);
  c.absolute_encoder = p.get_bool("absolute_encoder", c.absolute_encoder);
  c.sign_of_life_monitoring = p.get_bool("sign_of_life_monitoring", c.sign_of_life_monitoring);
  c.kv = p.get_double("kv", c.kv, 0.001, 100000);
  c.speed_tau_ms = p.get_double("speed_tau_ms", c.speed_tau_ms, 0, kMs);
  c.standstill_rpm = p.get_double("standstill_rpm", c.standstill_rpm, 0, kRpm);
  c.following_window = p.get_double("following_window", c.following_window, 0, kDint);
  c.following_error_limit =
      p.get_double("following_error_limit", c.following_error_limit, 0, kDint);
  c.target_window = p.get_double("target_window", c.target_window, 0, kDint);
  c.speed_window_rpm = p.get_double("speed_window_rpm", c.speed_window_rpm, 0, kRpm);
  c.homing_speed_rpm = p.get_double("homing_speed_rpm", c.homing_speed_rpm, 0, kRpm);
  c.home_switch = p.get_double("home_switch", c.home_switch, -kPos, kPos);
  c.home_position = p.get_double("home_position", c.home_position, -kPos, kPos);
  c.neg_limit = p.get_double("neg_limit", c.neg_limit, -kPos, kPos);
  c.pos_limit = p.get_double("pos_limit", c.pos_limit, -kPos, kPos);
  c.initial_position = p.get_double("initial_position", c.initial_position, -kPos, kPos);
  c.db_time_ms = p.get_double("db_time_ms", c.db_time_ms, 0, kMs);
  c.coast_time_ms = p.get_double("coast_time_ms", c.coast_time_ms, 0, kMs);
  using std::chrono::hours;
  using std::chrono::milliseconds;
  c.multiturn_clear_ms =
      std::chrono::duration_cast<milliseconds>(
          p.get_time("multiturn_clear_time", milliseconds(c.multiturn_clear_ms), TIME(0), hours(1)))
          .count();
  c.reset_ms = std::chrono::duration_cast<milliseconds>(
                   p.get_time("reset_time", milliseconds(c.reset_ms), TIME(0), hours(1)))
                   .count();
  p.reject_unknown();
  return c;
}
}  // namespace

HiwinE1Model::HiwinE1Model(const io::ModelParams& p) : HiwinE1Model(config_from(p)) {}

HiwinE1Model::HiwinE1Model(const HiwinE1Config& c)
    : cfg_(c), stop_thr_(std::max(1.0, rpm_to_cu_per_s(cfg_.standstill_rpm, cfg_.cu_per_rev))) {
  build_dictionary();
  enc_ = cfg_.initial_position;
  restart(true);
}

std::size_t HiwinE1Model::input_size() const { return in_bytes(cfg_.telegram); }
std::size_t HiwinE1Model::output_size() const { return out_bytes(cfg_.telegram); }

// ------------------------------------------------------------ dictionary
void HiwinE1Model::add(std::uint16_t pnu, std::uint8_t fmt, bool rw, double min, double max,
                       double def, std::size_t count, bool power_cycle) {
  Param e;
  e.format = fmt;
  e.writable = rw;
  e.power_cycle = power_cycle;
  e.min = min;
  e.max = max;
  e.value.assign(count, def);
  e.active = e.value;
  e.flash = e.value;
  dict_[pnu] = std::move(e);
}

void HiwinE1Model::build_dictionary() {
  constexpr std::uint8_t U16 = 0x06, I16 = 0x03, I32 = 0x04, U32 = 0x07, F32 = 0x08;
  constexpr double kI32Min = -2147483648.0, kI32Max = 2147483647.0;
  // PROFIdrive parameters, Table 4.1.1 (spec §6.1).
  add(kPnuTelegram, U16, false, 0, 65535, static_cast<double>(cfg_.telegram));
  add(kPnuSolTolerance, U16, true, 0, 65535, 5);
  add(kPnuOpMode, U16, false, 0, 65535, cfg_.telegram == TelegramType::Standard3 ? 1 : 2);
  add(kPnuFaultMsgCounter, U16, false, 0, 65535, 0);
  add(kPnuFaultCode, U16, false, 0, 65535, 0, 64);
  add(kPnuFaultNumber, U16, false, 0, 65535, 0, 64);
  add(kPnuFaultScaling, U16, false, 0, 65535, 8, 2);
  add(kPnuFaultSituations, U16, true, 0, 65535, 0);
  add(kPnuDriveId, U16, false, 0, 65535, 0, 7);
  {
    // Manufacturer 0xAAA, type 5, firmware 2.8 (0208) minor 16 = 2.8.16, the
    // first with 3200h (spec §7.10); date 2024, 1 February; one DO.
    auto& v = dict_[kPnuDriveId].value;
    v = {0x0AAA, 0x05, 208, 2024, 102, 1, 16};
    dict_[kPnuDriveId].active = dict_[kPnuDriveId].flash = v;
  }
  add(kPnuEncoderFormat, U32, false, 0, 4294967295.0, 0, 31);
  {
    // [INF] no values in the manual: header, rotary type 0, resolution in CU
    // per revolution, shifts 0, 65536 determinable revolutions (absolute).
    auto& v = dict_[kPnuEncoderFormat].value;
    v[0] = 0x5111;
    v[2] = cfg_.cu_per_rev;
    v[5] = cfg_.absolute_encoder ? 65536 : 0;
    dict_[kPnuEncoderFormat].active = dict_[kPnuEncoderFormat].flash = v;
  }
  // Manufacturer objects, Table 4.2.1 (spec §6.2).
  add(0x3000, U16, false, 0, 2, 0);
  add(0x3001, I32, false, kI32Min, kI32Max, 16777216);
  add(0x3056, U16, false, 0, 65535, 0);
  add(kGantryMode, U16, true, 1, 11, 1);
  add(0x3058, I32, true, kI32Min, kI32Max, 0);
  add(0x3059, I32, false, kI32Min, kI32Max, 0);
  add(0x3060, U16, true, 0, 1, 0);
  add(0x3061, U16, true, 0, 1, 0);
  add(kOvertravelStopMode, U16, true, 0, 1, 0);
  add(0x3110, U16, false, 0, 65535, 0);
  add(0x3111, U16, false, 0, 65535, 0);
  add(kAbsInit, I32, true, 0, 1, 0);
  for (std::uint16_t i = 0x3201; i <= 0x3209; ++i) add(i, I32, true, kI32Min, kI32Max, 0);
  for (std::uint16_t i = 0x3210; i <= 0x3214; ++i) add(i, F32, true, -3.40282e38, 3.40282e38, 0);
  add(kResetDrive, I16, true, 0, 1, 0);
  add(kSaveFlash, U16, true, 0, 1, 0);  // [INF] type "-" in the manual
  // Pt parameters quoted in the manual (spec §6.3), all Uint16.
  add(kPt001, U16, true, 0, 0xFFFF, 0, 1, true);
  add(kPt30A, U16, true, 0, 10000, 0);
  add(kPt316, U16, true, 0, 65535, 10000, 1, true);
  add(kPt317, U16, true, 1, 65535, 3000);
  add(kPt385, U16, true, 0, 100, 50, 1, true);
  add(kPt386, U16, true, 1, 100, 20);
  add(kPt402, U16, true, 0, 800, 800);
  add(kPt403, U16, true, 0, 800, 800);
  add(kPt483, U16, true, 0, 800, 30);
  add(kPt484, U16, true, 0, 800, 30);
  add(kPt533, U16, true, 1, 10000, 600);
  add(kPt534, U16, true, 2, 10000, 100);
  add(kPt537, U16, true, 2, 10000, 100);
  add(kPt538, U16, true, 2, 10000, 10);
  add(kPt53A, U16, true, 0, 1, 0);
  dict_[kPt53A].setup = true;
  add(kPt585, U16, true, 1, 10000, 50);
  // Ut monitors (0x4000 + Ut, spec §6.2). [INF] The manual's list (user
  // manual §14.3.4) is not in the extract; these five are our own: motor
  // speed, speed command (rpm), following error, single-turn position (CU),
  // multi-turn count. Read-only Int32, computed on read.
  for (std::uint16_t i = 0x4000; i <= 0x4004; ++i) add(i, I32, false, kI32Min, kI32Max, 0);
}

void HiwinE1Model::refresh_active() {
  act_.pt001 = p(kPt001);
  act_.pt30a = p(kPt30A);
  act_.pt316 = p(kPt316);
  act_.pt317 = p(kPt317);
  act_.pt533 = p(kPt533);
  act_.pt534 = p(kPt534);
  act_.pt537 = p(kPt537);
  act_.pt538 = p(kPt538);
  act_.pt53a = p(kPt53A);
  act_.ot_mode = p(kOvertravelStopMode);
  act_.sol_tolerance = p(kPnuSolTolerance);
  act_.sol_tol = static_cast<std::uint16_t>(act_.sol_tolerance);
  act_.acc534 = accel_of_ms(act_.pt534);
  act_.acc537 = accel_of_ms(act_.pt537);
  act_.acc538 = accel_of_ms(act_.pt538);
  act_.acc30a = accel_of_ms(act_.pt30a);
  act_.acc_coast = accel_of_ms(cfg_.coast_time_ms);
  act_.acc_db = accel_of_ms(cfg_.db_time_ms);
}

double HiwinE1Model::p(std::uint16_t pnu) const {
  auto it = dict_.find(pnu);
  return it == dict_.end() ? 0.0 : it->second.active[0];
}

double HiwinE1Model::parameter(std::uint16_t pnu, std::uint16_t sub) const {
  double v = 0;
  if (read_element(pnu, sub, v) != kOk) return std::numeric_limits<double>::quiet_NaN();
  return v;
}

std::uint16_t HiwinE1Model::set_parameter(std::uint16_t pnu, double value, std::uint16_t sub) {
  rest_repeat_ = false;
  auto it = dict_.find(pnu);
  if (it == dict_.end()) return 0x00;
  const std::uint16_t e = write_element(pnu, sub, value);
  return e == kOk ? 0xFFFF : e;
}

std::int64_t HiwinE1Model::multi_turn() const {
  return static_cast<std::int64_t>(std::floor(enc_ / cfg_.cu_per_rev));
}

std::uint16_t HiwinE1Model::read_element(std::uint16_t pnu, std::uint16_t sub, double& v) const {
  auto it = dict_.find(pnu);
  if (it == dict_.end()) return 0x00;
  if (sub >= it->second.value.size()) return 0x03;
  switch (pnu) {
    case kPnuFaultMsgCounter:
      v = fault_msg_counter_;
      return kOk;
    case kPnuFaultCode:
      v = fault_codes_[sub];
      return kOk;
    case kPnuFaultNumber:
      v = fault_numbers_[sub];
      return kOk;
    case kPnuFaultSituations:
      v = fault_situations_;
      return kOk;
    case kAbsInit:
      v = abs_init_;
      return kOk;
    case 0x3110:
      v = (overtravel_neg_ || overtravel_pos_) ? 1 : 0;
      return kOk;  // [INF]
    case 0x4000:
      v = std::round(cu_per_s_to_rpm(v_act_, cfg_.cu_per_rev));
      return kOk;
    case 0x4001:
      v = std::round(cu_per_s_to_rpm(v_set_, cfg_.cu_per_rev));
      return kOk;
    case 0x4002:
      v = std::round(p_set_ - enc_);
      return kOk;
    case 0x4003:
      v = std::floor(enc_ - static_cast<double>(multi_turn()) * cfg_.cu_per_rev);
      return kOk;
    case 0x4004:
      v = static_cast<double>(multi_turn());
      return kOk;
    default:
      v = it->second.value[sub];
      return kOk;
  }
}

std::uint16_t HiwinE1Model::write_element(std::uint16_t pnu, std::uint16_t sub, double v) {
  auto it = dict_.find(pnu);
  if (it == dict_.end()) return 0x00;
  Param& e = it->second;
  if (!e.writable) return 0x01;
  if (sub >= e.value.size()) return 0x03;
  if (v < e.min || v > e.max || std::isnan(v)) return 0x02;
  if (e.setup && pulses_enabled()) return 0x11;
  switch (pnu) {
    case kPnuFaultSituations:
      if (v != 0) return 0x06;
      fault_codes_.fill(0);
      fault_numbers_.fill(0);
      fault_situations_ = 0;
      ++fault_msg_counter_;
      return kOk;
    case kGantryMode:
      if (v != 1 && v != 2 && v != 11) return 0x14;
      break;
    case kPt001:
      if ((static_cast<unsigned>(v) & 0xF) > 2) return 0x14;
      break;
    case kAbsInit:
      if (v == 1) {
        if (pulses_enabled() || refuse_next_clear_) {
          abs_init_ = 16;
          refuse_next_clear_ = false;
        } else if (abs_init_ != 2) {
          abs_init_ = 2;
          abs_init_left_ms_ = static_cast<double>(cfg_.multiturn_clear_ms);
          clear_will_fail_ = fail_next_clear_ || !cfg_.absolute_encoder;
          fail_next_clear_ = false;
        }
      } else if (abs_init_ != 2) {
        abs_init_ = 0;
      }
      return kOk;
    case kResetDrive:
      if (v == 1) {
        reboot_left_ms_ = std::max<double>(1, static_cast<double>(cfg_.reset_ms));
        refresh_answering();
      }
      return kOk;
    case kSaveFlash:
      if (v == 1)
        for (auto& [k, p] : dict_) p.flash = p.value;
      return kOk;
    default:
      break;
  }
  e.value[sub] = e.format == 0x08 ? v : std::round(v);
  if (!e.power_cycle) e.active[sub] = e.value[sub];
  refresh_active();
  return kOk;
}

// ------------------------------------------------------- parameter channel
void HiwinE1Model::serve_parameter_request(std::span<const std::uint8_t> data) {
  ParamRequest r;
  ParamResponse resp;
  const ParseResult parsed = decode_request(data, r);
  resp.reference = r.reference;
  resp.do_id = r.do_id;
  resp.num_parameters = 1;
  auto fail = [&](std::uint16_t err) {
    const bool known = r.request_id == 0x01 || r.request_id == 0x02;
    resp.response_id =
        static_cast<std::uint8_t>(known ? (r.request_id | kResponseErrorFlag) : kResponseErrorFlag);
    resp.format = static_cast<std::uint8_t>(ParamFormat::Error);
    resp.num_values = 1;
    resp.error_no = err;
    response_len_ = resp.encode(response_);
  };
  if (data.size() < 4) {
    r = ParamRequest{};
    r.reference = data.empty() ? 0 : data[0];
    r.request_id = data.size() > 1 ? data[1] : 0;
    resp.reference = r.reference;
    return fail(0x16);
  }
  if (r.request_id != 0x01 && r.request_id != 0x02) return fail(0x21);
  if (r.num_parameters > 39) return fail(0x22);
  if (r.num_parameters != 1) return fail(0x23);
  if (parsed == ParseResult::TooShort) return fail(0x16);
  if (r.do_id != 0) return fail(0x19);
  if (r.attribute != kAttributeValue) {
    if (r.attribute == 0x20) return fail(0x09);  // description
    if (r.attribute == 0x30) return fail(0x0F);  // text
    return fail(0x16);
  }
  auto it = dict_.find(r.pnu);
  if (it == dict_.end()) return fail(0x00);
  const Param& e = it->second;
  const std::size_t count = e.value.size();
  const std::size_t n = r.num_elements == 0 ? 1 : r.num_elements;
  // Address checks shared by read and write.
  if (count == 1) {
    if (r.subindex != 0) return fail(0x04);
    if (n > 1) return fail(0x16);
  } else if (r.subindex >= count || r.subindex + n > count) {
    return fail(0x03);
  }
  if (r.request_id == 0x01) {
    if (6 + n * format_size(e.format) > io::kRecordMaxBytes || n > kParamMaxValues)
      return fail(0x15);
    resp.response_id = 0x01;
    resp.format = e.format;
    resp.num_values = static_cast<std::uint8_t>(n);
    for (std::size_t i = 0; i < n; ++i) {
      double v = 0;
      read_element(r.pnu, static_cast<std::uint16_t>(r.subindex + i), v);
      resp.values[i] = double_to_raw(v, e.format);
    }
    response_len_ = resp.encode(response_);
    return;
  }
  // Write.
  if (!e.writable) return fail(0x01);
  if (!is_value_format(r.format)) return fail(0x17);
  const bool same_size_bits = (r.format == 0x41 || r.format == 0x42 || r.format == 0x43) &&
                              format_size(r.format) == format_size(e.format);
  if (r.format != e.format && !same_size_bits) return fail(0x05);
  if (parsed == ParseResult::BadValues || r.num_values != n) return fail(0x18);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = raw_to_double(r.values[i], e.format);
    const std::uint16_t err = write_element(r.pnu, static_cast<std::uint16_t>(r.subindex + i), v);
    if (err != kOk) return fail(err);
  }
  resp.response_id = 0x02;
  response_len_ = resp.encode(response_);
}

io::RecordError HiwinE1Model::write_record(std::uint16_t index, std::span<const std::uint8_t> d) {
  if (index != kParamRecordIndex && index != kParamRecordIndexLocal &&
      index != kParamRecordIndexGlobal)
    return io::RecordError::InvalidIndex;
  rest_repeat_ = false;
  serve_parameter_request(d);
  return io::RecordError::None;
}

io::RecordError HiwinE1Model::read_record(std::uint16_t index, std::span<std::uint8_t> out,
                                          std::size_t& length) {
  length = 0;
  if (index != kParamRecordIndex && index != kParamRecordIndexLocal &&
      index != kParamRecordIndexGlobal)
    return io::RecordError::InvalidIndex;
  // [STD] a read before a response is ready gets a negative record response.
  if (response_len_ == 0) return io::RecordError::InvalidState;
  if (out.size() < response_len_) return io::RecordError::InvalidLength;
  std::copy_n(response_.begin(), response_len_, out.begin());
  length = response_len_;
  response_len_ = 0;  // a response is fetched once
  return io::RecordError::None;
}

// ------------------------------------------------------------- restarts
void HiwinE1Model::restart(bool reload_flash) {
  for (auto& [k, e] : dict_) {
    if (reload_flash) e.value = e.flash;
    e.active = e.value;
  }
  refresh_active();
  rest_repeat_ = false;
  stw1_ = prev_stw1_ = pos_stw2_prev_ = 0;
  cmd_ = Telegram111Out{};
  mdi_selected_ = false;
  nsoll_b_ = 0;
  g1_stw_ = 0;
  state_ = State::S1;
  reboot_left_ms_ = 0;
  refresh_answering();
  v_set_ = v_act_ = 0;
  if (!cfg_.absolute_encoder) {
    enc_ = 0;
    offset_ = 0;
    homed_ = false;
  }
  p_set_ = enc_;
  task_active_ = task_ack_ = task_rejecting_ = false;
  task_done_ = true;
  jog_active_ = homing_ = homing_found_ = false;
  fault_code_ = 0;
  cause_persists_ = false;
  sol_ = 0;
  sol_monitor_.reset();
  abs_init_ = 0;
  abs_init_left_ms_ = 0;
  response_len_ = 0;
}

void HiwinE1Model::power_cycle() { restart(true); }

// --------------------------------------------------------------- faults
bool HiwinE1Model::trip_alarm(std::uint16_t code, bool cause_persists) {
  if (e1_fault_number(code) == 0) return false;
  enter_fault(code);
  cause_persists_ = cause_persists;
  return true;
}

void HiwinE1Model::enter_fault(std::uint16_t code) {
  rest_repeat_ = false;
  fault_code_ = code;
  state_ = State::Fault;
  task_active_ = task_ack_ = task_rejecting_ = false;
  jog_active_ = homing_ = false;
  sol_monitor_.reset();
  // Fault buffer (PNU 945/947): 8 situations x 8 messages, situation 0 the
  // newest; one message per situation here.
  for (int s = 7; s > 0; --s)
    for (int m = 0; m < 8; ++m) {
      fault_codes_[s * 8 + m] = fault_codes_[(s - 1) * 8 + m];
      fault_numbers_[s * 8 + m] = fault_numbers_[(s - 1) * 8 + m];
    }
  for (int m = 0; m < 8; ++m) fault_codes_[m] = fault_numbers_[m] = 0;
  fault_codes_[0] = code;
  fault_numbers_[0] = e1_fault_number(code);
  fault_situations_ = static_cast<std::uint16_t>(std::min(8, fault_situations_ + 1));
  ++fault_msg_counter_;
}

// ------------------------------------------------------------ kinematics
double HiwinE1Model::ref_speed() const { return rpm_to_cu_per_s(act_.pt317, cfg_.cu_per_rev); }

double HiwinE1Model::accel_of_ms(double ms) const {
  return ms <= 0 ? std::numeric_limits<double>::infinity() : ramp_time_to_accel(ref_speed(), ms);
}

// Velocity setpoint towards vt: |v| grows with a, shrinks with d.
void HiwinE1Model::ramp_velocity(double vt, double a, double d, double dt) {
  const double v0 = v_set_;
  double v = v0;
  if (v == 0 || sgn(v) == sgn(vt)) {
    if (std::fabs(vt) > std::fabs(v)) {
      v = sgn(vt) * std::min(std::fabs(vt), std::fabs(v) + a * dt);
    } else {
      v = sgn(v) * std::max(std::fabs(vt), std::fabs(v) - d * dt);
    }
  } else {  // reversing: brake to 0 first
    v = sgn(v) * std::max(0.0, std::fabs(v) - d * dt);
  }
  v_set_ = v;
  p_set_ += 0.5 * (v0 + v) * dt;
}

// Trapezoidal move of the position setpoint to `target`. Returns true once
// the setpoint sits on the target at rest.
bool HiwinE1Model::move_to(double target, double vmax, double a, double d, double dt) {
  const double v0 = v_set_;
  const double s = target - p_set_;
  if (std::fabs(s) < 1e-9 && std::fabs(v0) < 1e-9) {
    p_set_ = target;
    v_set_ = 0;
    return true;
  }
  const double dir = sgn(s);
  const double vbrake = std::isinf(d) ? vmax : std::sqrt(2.0 * d * std::fabs(s));
  const double vdes = std::min(vmax, vbrake);
  double v;
  if (v0 * dir < 0) {  // moving away from the target: brake first
    v = sgn(v0) * std::max(0.0, std::fabs(v0) - d * dt);
  } else if (vdes > std::fabs(v0)) {
    v = dir * std::min(vdes, std::fabs(v0) + a * dt);
  } else {
    // Follow the braking curve; 1.5 x d absorbs the discretisation so the
    // setpoint lands on the target instead of creeping past it.
    v = dir * std::max(vdes, std::fabs(v0) - 1.5 * d * dt);
  }
  double pn = p_set_ + 0.5 * (v0 + v) * dt;
  const bool crossed = sgn(target - pn) != dir || std::fabs(target - pn) < 1e-6;
  if (crossed && std::fabs(v) <= std::max(vbrake * 1.01, 2.0 * d * dt) + 1e-9) {
    p_set_ = target;
    v_set_ = 0;
    return true;
  }
  p_set_ = pn;
  v_set_ = v;
  return false;
}

// Position loop: the encoder follows the setpoint as a first-order lag
// (gain kv), so the following error is v/kv at constant speed.
void HiwinE1Model::follow(double dt) {
  if (dt != follow_dt_) {  // the step is the same every time in virtual time: one exp()
    follow_dt_ = dt;
    follow_alpha_ = 1.0 - std::exp(-cfg_.kv * dt);
  }
  const double alpha = follow_alpha_;
  double n = enc_ + (p_set_ - enc_) * alpha;
  if (std::fabs(p_set_ - n) < 1e-6) n = p_set_;
  v_act_ = dt > 0 ? (n - enc_) / dt : 0;
  enc_ = n;
}

// Pulses off: dynamic brake (Pt001 digit 0 = 0/1) or free run (2).
void HiwinE1Model::coast(double dt) {
  const unsigned mode = static_cast<unsigned>(act_.pt001) & 0xF;
  const double dec = mode == 2 ? act_.acc_coast : act_.acc_db;
  const double v0 = v_act_;
  const double v = sgn(v0) * std::max(0.0, std::fabs(v0) - dec * dt);
  enc_ += 0.5 * (v0 + v) * dt;
  v_act_ = v;
  v_set_ = v;
  p_set_ = enc_;
  if (task_active_ || homing_ || jog_active_) task_done_ = false;
  task_active_ = task_rejecting_ = jog_active_ = homing_ = false;
}

// ---------------------------------------------------------- state machine
void HiwinE1Model::update_state_machine(bool rise_ack) {
  const bool on = has(stw1_, Stw1Pos::kOn);
  const bool no_off2 = has(stw1_, Stw1Pos::kNoCoastStop);
  const bool no_off3 = has(stw1_, Stw1Pos::kNoQuickStop);
  const bool enable = has(stw1_, Stw1Pos::kEnableOperation);
  if (state_ == State::Fault) {
    if (rise_ack && !cause_persists_) {
      fault_code_ = 0;
      state_ = State::S1;  // [STD] after acknowledgement: switching on inhibited
    }
    return;
  }
  // Priority OFF2 > OFF3 > OFF1 > disable operation (spec §5).
  if (!no_off2) {
    state_ = State::S1;
    return;
  }
  if (!no_off3) {
    if (state_ == State::S4 || state_ == State::S5Off1 || state_ == State::S5Off3)
      state_ = State::S5Off3;
    else
      state_ = State::S1;
    return;
  }
  switch (state_) {
    case State::S1:
      if (!on) state_ = State::S2;
      break;
    case State::S2:
      if (on) state_ = enable ? State::S4 : State::S3;
      break;
    case State::S3:
      if (!on)
        state_ = State::S2;
      else if (enable)
        state_ = State::S4;
      break;
    case State::S4:
      if (!on)
        state_ = State::S5Off1;
      else if (!enable)
        state_ = State::S3;
      break;
    default:
      break;  // S5 branches end at standstill (motion update)
  }
}

// -------------------------------------------------------- position mode
bool HiwinE1Model::update_position_mode(double dt, bool rise_task, bool rise_homing,
                                        bool rise_setref) {
  const double stop_thr = stop_thr_;
  // The flags the rest shortcut may change besides the motion values.
  const std::array<bool, 3> flags_was = {overtravel_neg_, overtravel_pos_, task_ack_};
  overtravel_neg_ = enc_ <= cfg_.neg_limit;
  overtravel_pos_ = enc_ >= cfg_.pos_limit;
  if (!has(stw1_, Stw1Pos::kActivateTask)) task_ack_ = false;

  if (rise_setref && std::fabs(v_set_) == 0) {
    offset_ = cfg_.home_position - enc_;
    homed_ = true;
  }
  if (!pulses_enabled()) {
    coast(dt);
    return false;
  }
  const double a_def = act_.acc534, d_def = act_.acc537;
  if (state_ == State::S5Off1 || state_ == State::S5Off3) {
    task_active_ = jog_active_ = homing_ = task_rejecting_ = false;
    const double d = state_ == State::S5Off1 ? d_def : act_.acc538;
    ramp_velocity(0, a_def, d, dt);
    follow(dt);
    if (v_set_ == 0 && std::fabs(v_act_) < stop_thr)
      state_ = state_ == State::S5Off1 ? State::S2 : State::S1;
    return false;
  }
  // S4
  const bool jog1 = has(stw1_, Stw1Pos::kJog1), jog2 = has(stw1_, Stw1Pos::kJog2);
  if (shortcuts_ && !rise_homing && !rise_task && !homing_ && !task_active_ && !task_rejecting_ &&
      !jog_active_ && jog1 == jog2 && v_set_ == 0 && p_set_ == enc_ && std::isfinite(enc_) &&
      dt > 0) {
    // At rest with nothing to start (the conveyor between two indexes):
    // what the general path below computes for it. No homing, task, jog or
    // reject starts or runs and nothing moves into a limit, so it would
    // ramp_velocity(0, ...): from a zero setpoint speed the new one is
    // 0 * max(0, -d * dt) = +0 (d >= 0, dt > 0), and p_set_ moves by
    // 0.5 * (+0) * dt = +0. follow(): p_set_ == enc_ (finite), so the lag
    // moves enc_ by +-0 * alpha, which is within 1e-6 of p_set_ and snaps to
    // it. The following error is 0.
    // Nothing changed when those writes leave every bit: the speeds were
    // +0, p_set_ not -0 (+0.0 turns it into +0) and enc_ p_set_'s bits.
    const auto bits = [](double d) { return std::bit_cast<std::uint64_t>(d); };
    const bool still =
        bits(v_set_) == 0 && bits(v_act_) == 0 && bits(p_set_) == bits(enc_) &&
        bits(p_set_) != bits(-0.0) &&
        flags_was == std::array<bool, 3>{overtravel_neg_, overtravel_pos_, task_ack_};
    v_set_ = 0.0;
    p_set_ += 0.0;
    v_act_ = (p_set_ - enc_) / dt;
    enc_ = p_set_;
    return still;
  }
  if (rise_homing && !task_active_ && !jog1 && !jog2) {
    homing_ = true;
    homing_found_ = false;
    homing_settle_ = false;
    homed_ = false;
    task_done_ = false;
    homing_dir_ = cfg_.home_switch >= enc_ ? 1.0 : -1.0;
  }
  if (homing_ && !has(stw1_, Stw1Pos::kStartHoming)) homing_ = false;  // aborted
  if (rise_task && mdi_selected_ && has(stw1_, Stw1Pos::kNoRejectTask) &&
      has(stw1_, Stw1Pos::kNoIntermediateStop) && cmd_.mdi_velocity > 0 && !homing_) {
    const bool absolute = cmd_.pos_stw1.absolute;
    const double target = absolute ? static_cast<double>(cmd_.mdi_tarpos)
                                   : p_set_ + offset_ + static_cast<double>(cmd_.mdi_tarpos);
    task_target_ = target - offset_;
    task_v_ = mdi_velocity_to_cu_per_s(cmd_.mdi_velocity);
    const double acc = std::clamp<int>(cmd_.mdi_acc, 1, 16384) / kPercent14;
    const double dec = std::clamp<int>(cmd_.mdi_dec, 1, 16384) / kPercent14;
    task_a_ = a_def * acc;
    task_d_ = d_def * dec;
    task_active_ = true;
    task_done_ = false;
    task_ack_ = true;
    task_rejecting_ = false;
    jog_active_ = false;
  }
  if (task_active_ && !has(stw1_, Stw1Pos::kNoRejectTask)) {
    task_active_ = false;  // reject: discard with the emergency ramp [STD]
    task_rejecting_ = true;
    task_done_ = false;
  }
  // Overtravel: motion into an active limit stops and drops the task.
  const double ot_dec = act_.ot_mode == 1 ? d_def : act_.acc538;
  const bool into_limit = (overtravel_neg_ && v_set_ < 0) || (overtravel_pos_ && v_set_ > 0);
  if (into_limit) {
    task_active_ = homing_ = false;
    task_rejecting_ = true;
    task_done_ = false;
  }
  double jog_dir = 0;
  if (jog1 != jog2 && !task_active_ && !homing_) {
    jog_dir = jog1 ? 1.0 : -1.0;
    if (act_.pt53a == 1) jog_dir = -jog_dir;  // Pt53A reversal (spec §4.2)
    if ((jog_dir < 0 && overtravel_neg_) || (jog_dir > 0 && overtravel_pos_)) jog_dir = 0;
  }
  jog_active_ = jog_dir != 0 || (jog_active_ && v_set_ != 0);
  if (jog_dir != 0) task_done_ = false;

  if (task_rejecting_) {
    ramp_velocity(0, a_def, into_limit ? ot_dec : act_.acc538, dt);
    if (v_set_ == 0) task_rejecting_ = false;
  } else if (homing_) {
    if (!homing_found_) {
      const double before = enc_ - cfg_.home_switch;
      ramp_velocity(homing_dir_ * rpm_to_cu_per_s(cfg_.homing_speed_rpm, cfg_.cu_per_rev), a_def,
                    d_def, dt);
      const double after = p_set_ - cfg_.home_switch;
      if (before == 0 || sgn(before) != sgn(after) || after == 0) {
        homing_found_ = true;
        offset_ = cfg_.home_position - cfg_.home_switch;  // position at the switch
      }
    } else {
      // Stop; completion shows one cycle after standstill so the PLC always
      // sees POS_ZSW1.11 = 1 / ZSW1.11 = 0 for at least one frame.
      ramp_velocity(0, a_def, d_def, dt);
      if (v_set_ == 0) {
        if (homing_settle_) {
          homing_ = false;
          homed_ = true;
        }
        homing_settle_ = true;
      }
    }
  } else if (task_active_) {
    if (!has(stw1_, Stw1Pos::kNoIntermediateStop)) {
      ramp_velocity(0, task_a_, task_d_, dt);  // pause, keep the task
    } else {
      const double ovr = cfg_.telegram == TelegramType::Hiwin111
                             ? std::min<double>(cmd_.override_, 32767) / kPercent14
                             : 1.0;
      if (move_to(task_target_, task_v_ * ovr, task_a_, task_d_, dt)) {
        task_active_ = false;
        task_done_ = true;
      }
    }
  } else if (jog_dir != 0) {
    ramp_velocity(jog_dir * rpm_to_cu_per_s(act_.pt533, cfg_.cu_per_rev), a_def, d_def, dt);
  } else {
    ramp_velocity(0, a_def, d_def, dt);
  }
  follow(dt);
  if (std::fabs(p_set_ - enc_) > cfg_.following_error_limit) enter_fault(kFaultFollowingError);
  return false;
}

// ------------------------------------------------------------ speed mode
void HiwinE1Model::update_speed_mode(double dt) {
  const double stop_thr = std::max(1.0, rpm_to_cu_per_s(cfg_.standstill_rpm, cfg_.cu_per_rev));
  if (!pulses_enabled()) {
    coast(dt);
    return;
  }
  double vt = 0, d = accel_of_ms(act_.pt537);
  if (state_ == State::S4) {
    const double vmax = rpm_to_cu_per_s(act_.pt316, cfg_.cu_per_rev);
    vt = std::clamp(nist_b_to_speed(nsoll_b_, ref_speed()), -vmax, vmax);
  } else if (state_ == State::S5Off3) {
    d = act_.acc30a;
  }
  ramp_velocity(vt, act_.acc534, d, dt);
  const double tau = cfg_.speed_tau_ms / 1000.0;
  const double va0 = v_act_;
  v_act_ = tau > 0 ? v_act_ + (v_set_ - v_act_) * (1.0 - std::exp(-dt / tau)) : v_set_;
  if (std::fabs(v_act_ - v_set_) < 1e-6) v_act_ = v_set_;
  enc_ += 0.5 * (va0 + v_act_) * dt;
  p_set_ = enc_;
  speed_target_ = vt;
  if ((state_ == State::S5Off1 || state_ == State::S5Off3) && v_set_ == 0 &&
      std::fabs(v_act_) < stop_thr)
    state_ = state_ == State::S5Off1 ? State::S2 : State::S1;
}

// ------------------------------------------------------------------ step
void HiwinE1Model::step(TIME now, TIME dt_ns, std::span<const std::uint8_t> from_plc,
                        std::span<std::uint8_t> to_plc) {
  // The drive at rest repeating itself (rest_repeat_; no reboot or 3200h
  // clear can be running then): the PLC's bytes but STW2 are the last
  // step's, which changed nothing, so stw1_, POS_STW2 and the setpoints stay
  // and no edge rises; the state machine, the motion update and the
  // telegram's key would find what they found then. What is left is what
  // step_full() does with STW2 that is read later (the sign-of-life) and
  // the telegram copy. The decoded STW2 (decoded_.stw2) and its copy in the
  // setpoints (cmd_.stw2) are not written: decode_111() writes
  // decoded_.stw2 before every read of it, and of cmd_ only the setpoints
  // are read (a copy of the whole, cmd_ = t, rewrites it too). A
  // sign-of-life failure (the monitor fed in place) takes step_full() from
  // the start instead.
  using T = Telegram111Out;
  if (rest_repeat_ && dt_ns > TIME::zero() && from_plc.size() >= T::kBytes) {
    // The bytes but STW2 the decoded ones: three 8-byte words, STW2
    // (bytes 6 and 7) shifted out of the first one's difference.
    static_assert(T::kBytes == 24 && T::kStw2 == 6);
    const auto diff = [p = from_plc.data(), k = decoded_bytes_.data()](std::size_t off) {
      std::uint64_t a, b;
      std::memcpy(&a, p + off, sizeof a);
      std::memcpy(&b, k + off, sizeof b);
      return a ^ b;
    };
    const std::uint64_t d0 = diff(0);
    const std::uint64_t d0_but_stw2 =
        std::endian::native == std::endian::little ? d0 << 16 : d0 >> 16;
    if ((d0_but_stw2 | diff(8) | diff(16)) == 0) {
      const Stw2 stw2 = Stw2::from(wire::u16(from_plc, T::kStw2));
      // The monitor is fed in place. A failure is a loss (update() returns
      // !lost_, and nothing but reset() clears lost_): step_full() from the
      // start then feeds it the same value, fails again and enters the
      // fault, which resets it; nothing reads it in between, so it is not
      // put back.
      // (Monitoring and a healthy sign-of-life marked likely: the usual
      // path laid out straight.)
      bool fed = true;
      if (cfg_.sign_of_life_monitoring) [[likely]]
        fed = sol_monitor_.update(stw2.controller_sign_of_life, act_.sol_tol);
      if (fed) [[likely]] {
        const std::uint8_t sol = kSolAfterStep[sol_frozen_][sol_];
        sol_ = sol;
        // put_inputs() as it goes for a repeat: telegram 111 (only its
        // decode finds the same words) in S4 (pulses enabled), so no
        // switch on the telegram and no test of the state. ZSW2 from the
        // register (the copy could alias sol_ for the compiler).
        Zsw2 zsw2;
        zsw2.drive_sign_of_life = sol;
        zsw2.pulses_enabled = true;
        const std::uint16_t zsw2_word = zsw2.word();
        std::memcpy(to_plc.first<Telegram111In::kBytes>().data(), encoded_.data(),
                    Telegram111In::kBytes);
        wire::put16(to_plc, Telegram111In::kZsw2, zsw2_word);
        return;
      }
    }
  }
  step_full(now, dt_ns, from_plc, to_plc);
}

void HiwinE1Model::step_full(TIME /*now*/, TIME dt_ns, std::span<const std::uint8_t> from_plc,
                             std::span<std::uint8_t> to_plc) {
  const double dt = static_cast<double>(dt_ns.count()) * 1e-9;
  const double dt_ms = dt * 1000.0;
  if (reboot_left_ms_ > 0) {
    reboot_left_ms_ -= dt_ms;
    refresh_answering();
    if (reboot_left_ms_ <= 0) restart(false);  // warm restart: parameter RAM kept
    return;
  }
  const bool init_idle = abs_init_ != 2;  // no 3200h clear running (it moves the encoder)
  if (abs_init_ == 2) {
    abs_init_left_ms_ -= dt_ms;
    if (pulses_enabled()) clear_will_fail_ = true;
    if (abs_init_left_ms_ <= 0) {
      if (clear_will_fail_) {
        abs_init_ = 32;
      } else {
        enc_ -= static_cast<double>(multi_turn()) * cfg_.cu_per_rev;  // single-turn only
        p_set_ = enc_;
        offset_ = 0;
        homed_ = false;
        abs_init_ = 4;
      }
    }
  }

  // Decode the PLC's telegram; with STW1.10 = 0 keep the last valid values.
  std::uint16_t stw1 = 0, pos_stw2 = 0;
  std::uint8_t sol_in = 0;
  bool same_words = false;  // telegram 111: the bytes but STW2 are the last step's
  switch (cfg_.telegram) {
    case TelegramType::Standard3: {
      const auto t = Telegram3Out::decode(from_plc);
      stw1 = t.stw1.word();
      sol_in = t.stw2.controller_sign_of_life;
      if (t.stw1.control_by_plc) {
        nsoll_b_ = t.nsoll_b;
        g1_stw_ = t.g1_stw.word();
      }
      break;
    }
    case TelegramType::Standard9: {
      const auto t = Telegram9Out::decode(from_plc);
      stw1 = t.stw1.word();
      sol_in = t.stw2.controller_sign_of_life;
      if (t.stw1.control_by_plc) {
        cmd_.stw1 = t.stw1;
        cmd_.pos_stw1.absolute = t.mdi_mode.absolute;
        cmd_.pos_stw1.activate_mdi = t.satzanw.activate_mdi;
        cmd_.override_ = 0x4000;
        cmd_.mdi_tarpos = t.mdi_tarpos;
        cmd_.mdi_velocity = t.mdi_velocity;
        cmd_.mdi_acc = t.mdi_acc;
        cmd_.mdi_dec = t.mdi_dec;
        mdi_selected_ = t.satzanw.activate_mdi;
      }
      break;
    }
    case TelegramType::Hiwin111: {
      const Telegram111Out& t = decode_111(from_plc, same_words);
      if (from_plc.size() >= Telegram111Out::kBytes) {
        stw1 = static_cast<std::uint16_t>(wire::u16(from_plc, Telegram111Out::kStw1) &
                                          Stw1Pos::kDefined);
        pos_stw2 = static_cast<std::uint16_t>(wire::u16(from_plc, Telegram111Out::kPosStw2) &
                                              PosStw2::kDefined);
      } else {
        stw1 = t.stw1.word();
        pos_stw2 = t.pos_stw2.word();
      }
      sol_in = t.stw2.controller_sign_of_life;
      if (t.stw1.control_by_plc) {
        cmd_ = t;
        mdi_selected_ = t.pos_stw1.activate_mdi;
      }
      break;
    }
  }
  if (has(stw1, Stw1Pos::kControlByPlc))
    stw1_ = stw1;
  else
    pos_stw2 = pos_stw2_prev_;
  const std::uint16_t rise = static_cast<std::uint16_t>(stw1_ & ~prev_stw1_);
  const bool rise_setref = has(pos_stw2, PosStw2::kSetReferencePoint) &&
                           !has(pos_stw2_prev_, PosStw2::kSetReferencePoint);
  const bool words_kept = stw1_ == prev_stw1_ && pos_stw2 == pos_stw2_prev_;
  pos_stw2_prev_ = pos_stw2;

  if (!sol_frozen_) sol_ = next_sign_of_life(sol_);
  if (cfg_.sign_of_life_monitoring && state_ != State::Fault) {
    if (!sol_monitor_.update(sol_in, act_.sol_tol)) enter_fault(kFaultSignOfLife);
  }

  const bool in_s4 = state_ == State::S4;
  update_state_machine(has(rise, Stw1Pos::kFaultAck));
  bool still = false;
  if (cfg_.telegram == TelegramType::Standard3) {
    update_speed_mode(dt);
    const std::uint16_t g1_rise = static_cast<std::uint16_t>(g1_stw_ & ~g1_prev_);
    g1_ack_in_progress_ = has(g1_rise, G1Stw::kAckSensorError);
    g1_prev_ = g1_stw_;
  } else {
    still = update_position_mode(dt, has(rise, Stw1Pos::kActivateTask),
                                 has(rise, Stw1Pos::kStartHoming), rise_setref);
  }
  prev_stw1_ = stw1_;
  write_inputs(to_plc);
  // This step changed nothing but the sign-of-life (see rest_repeat_): the
  // words and setpoints were the last step's, the state stayed S4 (a fault
  // from the sign-of-life or the motion leaves it), the rest shortcut kept
  // every bit, and no 3200h clear ran.
  rest_repeat_ = still && same_words && words_kept && in_s4 && state_ == State::S4 && init_idle;
}

// Telegram111Out::decode once per change of the PLC's words: they stand
// still between commands but for the sign-of-life in STW2, which is taken
// from its word every step. A pure function of the bytes, so the cache
// cannot go stale (restart and power cycle need not touch it).
const Telegram111Out& HiwinE1Model::decode_111(std::span<const std::uint8_t> b, bool& same) {
  using T = Telegram111Out;
  same = false;
  if (b.size() < T::kBytes) {
    decoded_valid_ = false;
    decoded_ = T::decode(b);
    return decoded_;
  }
  const std::uint8_t* p = b.data();
  if (!decoded_valid_ || std::memcmp(p, decoded_bytes_.data(), T::kStw2) != 0 ||
      std::memcmp(p + T::kStw2 + 2, decoded_bytes_.data() + T::kStw2 + 2,
                  T::kBytes - T::kStw2 - 2) != 0) {
    decoded_ = T::decode(b);
    std::memcpy(decoded_bytes_.data(), p, T::kBytes);
    decoded_valid_ = true;
  } else {
    decoded_.stw2 = Stw2::from(wire::u16(b, T::kStw2));
    same = true;
  }
  return decoded_;
}

// Everything encode_inputs() reads but the sign-of-life and the
// configuration (fixed at construction), the doubles as their bits: equal
// keys give equal telegrams (ZSW2 aside).
inline HiwinE1Model::InputsKey HiwinE1Model::inputs_key() const {
  const auto bits = [](double d) { return std::bit_cast<std::uint64_t>(d); };
  const auto flag = [](bool f, unsigned at) { return static_cast<std::uint64_t>(f) << at; };
  const std::uint64_t words =
      static_cast<std::uint64_t>(stw1_ & (Stw1Pos::kNoCoastStop | Stw1Pos::kNoQuickStop)) |
      static_cast<std::uint64_t>(injected_warning_) << 16 |
      static_cast<std::uint64_t>(fault_code_) << 32 | static_cast<std::uint64_t>(g1_stw_) << 48;
  const std::uint64_t flags = static_cast<std::uint64_t>(state_) | flag(overtravel_neg_, 8) |
                              flag(overtravel_pos_, 9) | flag(task_done_, 10) |
                              flag(task_active_, 11) | flag(homing_, 12) | flag(jog_active_, 13) |
                              flag(task_rejecting_, 14) | flag(homed_, 15) | flag(task_ack_, 16) |
                              flag(mdi_selected_, 17) | flag(g1_ack_in_progress_, 18);
  return {bits(v_act_),        bits(v_set_),     bits(p_set_), bits(enc_), bits(offset_),
          bits(speed_target_), bits(act_.pt317), words,        flags};
}

static_assert(Telegram3In::kBytes <= Telegram111In::kBytes &&
              Telegram9In::kBytes <= Telegram111In::kBytes);

// The telegram encoded once per change of its key; every step copies it
// and puts in ZSW2 with this step's sign-of-life (the word encode_inputs()
// would write there).
void HiwinE1Model::write_inputs(std::span<std::uint8_t> to_plc) {
  const InputsKey key = inputs_key();
  std::uint64_t diff = 0;  // no memcmp call
  for (std::size_t i = 0; i < key.size(); ++i) diff |= key[i] ^ encoded_key_[i];
  if (!encoded_valid_ || diff != 0) {
    encode_inputs(encoded_);
    encoded_key_ = key;
    encoded_valid_ = shortcuts_;
  }
  put_inputs(to_plc);
}

// The telegram as last encoded, with this step's ZSW2.
void HiwinE1Model::put_inputs(std::span<std::uint8_t> to_plc) {
  Zsw2 zsw2;
  zsw2.drive_sign_of_life = sol_;
  zsw2.pulses_enabled = pulses_enabled();
  // Whole telegrams: constant sizes, so the copies are inline.
  switch (cfg_.telegram) {
    case TelegramType::Standard3:
      std::memcpy(to_plc.first<Telegram3In::kBytes>().data(), encoded_.data(), Telegram3In::kBytes);
      wire::put16(to_plc, Telegram3In::kZsw2, zsw2.word(false));
      break;
    case TelegramType::Standard9:
      std::memcpy(to_plc.first<Telegram9In::kBytes>().data(), encoded_.data(), Telegram9In::kBytes);
      wire::put16(to_plc, Telegram9In::kZsw2, zsw2.word());
      break;
    case TelegramType::Hiwin111:
      std::memcpy(to_plc.first<Telegram111In::kBytes>().data(), encoded_.data(),
                  Telegram111In::kBytes);
      wire::put16(to_plc, Telegram111In::kZsw2, zsw2.word());
      break;
  }
}

void HiwinE1Model::encode_inputs(std::span<std::uint8_t> to_plc) const {
  const bool fault = state_ == State::Fault;
  const bool pulses = pulses_enabled();
  std::uint16_t z = 0;
  switch (state_) {
    case State::S1:
      z = Zsw1Pos::kSwitchOnInhibited |
          put(has(stw1_, Stw1Pos::kNoCoastStop), Zsw1Pos::kNoCoastStop) |
          put(has(stw1_, Stw1Pos::kNoQuickStop), Zsw1Pos::kNoQuickStop);
      break;
    case State::S2:
      z = Zsw1Pos::kReadyToSwitchOn | Zsw1Pos::kNoCoastStop | Zsw1Pos::kNoQuickStop;
      break;
    case State::S3:
      z = Zsw1Pos::kReadyToSwitchOn | Zsw1Pos::kReadyToOperate | Zsw1Pos::kNoCoastStop |
          Zsw1Pos::kNoQuickStop;
      break;
    case State::S4:
      z = Zsw1Pos::kReadyToSwitchOn | Zsw1Pos::kReadyToOperate | Zsw1Pos::kOperationEnabled |
          Zsw1Pos::kNoCoastStop | Zsw1Pos::kNoQuickStop;
      break;
    case State::S5Off1:
      z = Zsw1Pos::kReadyToSwitchOn | Zsw1Pos::kNoCoastStop | Zsw1Pos::kNoQuickStop;
      break;
    case State::S5Off3:
      z = Zsw1Pos::kNoCoastStop;
      break;
    case State::Fault:
      z = Zsw1Pos::kFault | put(has(stw1_, Stw1Pos::kNoCoastStop), Zsw1Pos::kNoCoastStop) |
          put(has(stw1_, Stw1Pos::kNoQuickStop), Zsw1Pos::kNoQuickStop);
      break;
  }
  z |= Zsw1Pos::kControlRequested;  // normal bus operation (spec §10.1)
  const std::uint16_t warn = injected_warning_                      ? injected_warning_
                             : (overtravel_neg_ || overtravel_pos_) ? kWarnOvertravel
                                                                    : std::uint16_t{0};
  if (warn) z |= Zsw1Pos::kWarning;
  const double stop_thr = stop_thr_;
  const bool stopped = std::fabs(v_act_) < stop_thr;
  Zsw2 zsw2;
  zsw2.drive_sign_of_life = sol_;
  zsw2.pulses_enabled = pulses;
  const std::int32_t nist = speed_to_nsoll_b(cu_per_s_to_rpm(v_act_, cfg_.cu_per_rev), act_.pt317);

  if (cfg_.telegram == TelegramType::Standard3) {
    const double win = rpm_to_cu_per_s(cfg_.speed_window_rpm, cfg_.cu_per_rev);
    if (pulses && std::fabs(v_set_ - v_act_) <= win) z |= Zsw1Speed::kSpeedErrorInTolerance;
    if (pulses && std::fabs(speed_target_ - v_act_) <= win) z |= Zsw1Speed::kSpeedReached;
    Telegram3In t;
    t.zsw1 = Zsw1Speed::from(z);
    t.nist_b = nist;
    t.zsw2 = zsw2;
    G1Zsw g;
    g.parking_active = has(g1_stw_, G1Stw::kActivateParking);
    g.error_ack_in_process = g1_ack_in_progress_;
    t.g1_zsw = g;
    t.g1_xist1 =
        static_cast<std::uint32_t>(static_cast<std::int64_t>(drive::detail::llround_inline(enc_)));
    t.g1_xist2 = 0;
    t.encode(to_plc);
    return;
  }
  const double fe = std::fabs(p_set_ - enc_);
  if (pulses && fe <= cfg_.following_window) z |= Zsw1Pos::kFollowingErrorInTolerance;
  if (pulses && task_done_ && !task_active_ && !homing_ && !jog_active_ && !task_rejecting_ &&
      v_set_ == 0 && fe <= cfg_.target_window)
    z |= Zsw1Pos::kTargetReached;
  if (homed_) z |= Zsw1Pos::kHomePositionSet;
  if (task_ack_) z |= Zsw1Pos::kTaskAck;
  if (stopped) z |= Zsw1Pos::kMotorStopped;
  const auto xist = static_cast<std::int32_t>(static_cast<std::uint32_t>(
      static_cast<std::int64_t>(drive::detail::llround_inline(enc_ + offset_))));
  if (cfg_.telegram == TelegramType::Standard9) {
    Telegram9In t;
    t.zsw1 = Zsw1Pos::from(z);
    t.aktsatz.mdi_active = mdi_selected_;
    t.zsw2 = zsw2;
    t.xist_a = xist;
    t.encode(to_plc);
    return;
  }
  Telegram111In t;
  t.zsw1 = Zsw1Pos::from(z);
  t.pos_zsw1.negative_overtravel = overtravel_neg_;
  t.pos_zsw1.positive_overtravel = overtravel_pos_;
  t.pos_zsw1.jog_active = jog_active_;
  t.pos_zsw1.homing_active = homing_;
  t.pos_zsw1.mdi_active = mdi_selected_;
  t.pos_zsw2.setpoint_available = task_active_;
  t.pos_zsw2.moving_forward = v_act_ > stop_thr;
  t.pos_zsw2.moving_backward = v_act_ < -stop_thr;
  t.pos_zsw2.traversing_active = task_active_;
  t.zsw2 = zsw2;
  t.meldw.torque_limit_not_active = true;
  t.meldw.no_motor_overload_warning = true;
  t.meldw.no_i2t_warning = true;
  t.meldw.speed_deviation_in_tolerance = true;  // "not functional: always 1"
  t.meldw.controller_enabled = pulses;
  t.meldw.drive_ready = !fault && state_ != State::S1;
  t.meldw.pulses_enabled = pulses;
  t.xist_a = xist;
  t.nist_b = nist;
  t.fault_code = fault ? fault_code_ : 0;
  t.warn_code = warn;
  t.encode(to_plc);
}

PLC_REGISTER_DEVICE_MODEL("hiwin_e1", HiwinE1Model)

}  // namespace plc::sim

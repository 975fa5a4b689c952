#include "plc/sim/nord_profisafe_model.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <tuple>

#include "plc/fb/safety/control_status_byte.hpp"
#include "plc/fb/safety/nord_error_codes.hpp"
#include "plc/fb/safety/nord_fdata_bits.hpp"
#include "plc/fb/safety/safety_pdu.hpp"

namespace plc::sim {

namespace err = plc::safety::nord::err;
namespace nin = plc::safety::nord::in;
namespace nout = plc::safety::nord::out;
namespace cb = plc::safety::cb;
namespace sbit = plc::safety::sb;
using plc::safety::nord::get;
using plc::safety::nord::put;
using namespace std::chrono_literals;

NordProfisafeModel::NordProfisafeModel(const io::ModelParams& p)
    : ip_(NordIParams::from(p)), fn_(ip_) {
  dip_ = static_cast<std::uint16_t>(p.get_int("dip_address", 1, 0, 65535));
  p831_ = static_cast<std::uint16_t>(p.get_int("p831", 0, 0, 65535));
  max_sil_ = static_cast<int>(p.get_int("max_sil", 3, 0, 3));
  speed_rpm_ = p.get_double("speed_rpm", 0.0, -100000, 100000);  // beyond any motor, finite
  si_raw_ = {p.get_bool("si1", false), p.get_bool("si2", false)};
  si_ = si_raw_;
  p.reject_unknown();
  for (unsigned so = 0; so < ossd_of_.size(); ++so) {
    bool cmd[3] = {(so & 1u) != 0, (so & 2u) != 0, (so & 4u) != 0};
    if (ip_.p800[1] == 1) cmd[0] = cmd[1] = cmd[0] && cmd[1];  // SO1+SO2 dual channel
    for (unsigned i = 0; i < 3; ++i)
      ossd_of_[so] |= static_cast<std::uint32_t>(cmd[i] && ip_.p802[2 + i] == 1) << (8 * i);
  }
  refresh_inc_per_s();
  refresh_si_causes();
  power_cycle();
}

void NordProfisafeModel::reset_volatile() {
  pas_.no_fpar = true;
  set_crc1(0);
  wd_ = {};
  cn_ = 0;
  last_toggle_ = false;
  pas_.ce_crc = pas_.wd_timeout = cons_nr_r_ = false;
  pas_.fault_fv = pas_.host_fv = true;
  requested_ = {};
  applied_ = {};
  chan_ack_prev_ = false;
  static constexpr std::uint16_t kCodes[kQCount] = {err::kSlsViolated,
                                                    err::kSsrViolated,
                                                    err::kSdiPViolated,
                                                    err::kSdiNViolated,
                                                    err::kSosViolated,
                                                    err::kSls,
                                                    err::kSsr,
                                                    err::kSdiP,
                                                    err::kSdiN,
                                                    err::kSos,
                                                    err::kSo1NotEnabled,
                                                    err::kSo2NotEnabled,
                                                    err::kSo3NotEnabled,
                                                    err::kSi1NotEnabled,
                                                    err::kSi2NotEnabled,
                                                    err::kInput1Diag,
                                                    err::kInput2Diag,
                                                    err::kDiscrepancy,
                                                    0};
  for (int i = 0; i < kQCount; ++i) {
    q_[i] = QError{};
    q_[i].code = kCodes[i];
    // Reintegration >= 10 s after a violation (§1.5) or a clock-monitoring
    // error (§2.8).
    if (i <= kQSos || i == kQSi1Clock || i == kQSi2Clock) q_[i].hold = 10s;
  }
  q_[kQSo1Off].channel = 0;
  q_[kQSo2Off].channel = 1;
  q_[kQSo3Off].channel = 2;
  active_q_ = 0;
  refresh_module_fault();
  fatal_code_ = 0;
  p841_ = p842_ = 0;
  code_events_ = 0;
  injected_cause_ = false;
  chan_passive_ = {};
  discrepancy_timing_ = discrepancy_fault_ = false;
  respond_pending_ = false;
  ossd_ = {};
  pdu_ = {};
  sent_ = {};
  accepted_ = {};
  sent_head_ = accepted_head_ = 0;
  req_hist_ = {};
  corrupt_req_n_ = corrupt_resp_n_ = repeat_resp_ = repeat_req_ = foreign_ = 0;
  injecting_ = false;
  drop_until_ = TIME{};
  drop_start_pending_ = false;
  stopped_ = false;
  set_answering_now(true);  // answering() is !stopped_
  fn_.reset();
  at_rest_ = steady_ = false;
  resp_fresh_ = false;
}

void NordProfisafeModel::power_cycle() {
  reset_volatile();
  // The device's frame goes to zeros; frames already on the way still
  // arrive (the channel is not part of the device).
  NordFrameTag t;
  t.id = ++frames_sent_;
  t.sent = t.produced = now_;
  channel_.send(now_, pdu_, t);
  // The F-address is read at power-on: DIP 2-9, or P831 when the DIPs are 0
  // (spec §6.4). 0 and 65535 are refused: the DIP-read fatal error 5726.
  f_address_ = dip_ != 0 ? dip_ : p831_;
  address_valid_ = !(dip_ > 255 || f_address_ == 0 || f_address_ == 65535);
  std::uint16_t code = 0;
  if (!address_valid_) {
    code = err::kDipRead;
  } else {
    code = ip_.check();
  }
  if (permanent_5792_) code = err::kSystemErrorMax;
  config_fatal_ = code;
  if (code) {
    fatal_code_ = code;
    raise_code(code);
  }
}

void NordProfisafeModel::raise_code(std::uint16_t code) {
  if (p841_ == code) return;
  // A latched fatal code stays the current one until the power cycle; a
  // later q code (a refused parameter block, a channel fault) is answered
  // with its own number where it arises but does not displace it.
  if (fatal_code_ != 0 && p841_ == fatal_code_ && code != fatal_code_) return;
  if (p841_ != 0) p842_ = p841_;
  p841_ = code;
  code_since_ = now_;
  ++code_events_;
}

void NordProfisafeModel::inject_device_fault(std::uint16_t code, bool fatal) {
  at_rest_ = steady_ = false;
  if (fatal) {
    if (fatal_code_ == 0) fatal_code_ = code;
    raise_code(code);
    return;
  }
  QError& e = q_[kQInjected];
  e.code = code;
  // OSSD / clock / input diagnostics persist >= 10 s (spec §5.5).
  e.hold = (code >= err::kOutput1 && code <= err::kInput2Diag) ? TIME(10s) : TIME{};
  e.channel = (code >= err::kOutput1 && code <= err::kOutput3) ? code - err::kOutput1 : -1;
  injected_cause_ = true;
  refresh_module_fault();  // an active injected error may now count for the module
}

void NordProfisafeModel::inject_system_error() {
  at_rest_ = steady_ = false;
  ++p848_;
  if (p848_ > 15) permanent_5792_ = true;
  const std::uint16_t code = permanent_5792_ ? err::kSystemErrorMax : err::kSystemError;
  fatal_code_ = code;
  raise_code(code);
}

void NordProfisafeModel::corrupt_requests(int n, std::size_t byte, std::uint8_t mask) {
  corrupt_req_n_ = n;
  injecting_ = true;
  steady_ = false;
  corrupt_req_byte_ = byte % kPdu;
  corrupt_req_mask_ = mask;
}

void NordProfisafeModel::corrupt_responses(int n, std::size_t byte, std::uint8_t mask) {
  corrupt_resp_n_ = n;
  injecting_ = true;
  steady_ = false;
  corrupt_resp_byte_ = byte % kPdu;
  corrupt_resp_mask_ = mask;
}

// Kept in pas_.module_fault: it depends only on which q errors are active and
// their channels, and evaluate() asks several times a step.
void NordProfisafeModel::refresh_module_fault() {
  pas_.module_fault = false;
  for (int i = 0; i < kQCount; ++i) {
    const QError& e = q_[i];
    if (!e.active) continue;
    if (ip_.p801 == 0) {
      pas_.module_fault = true;
      return;
    }
    // Channel passivation (P801 = 1): violations are only reported, SO
    // errors passivate their channel, everything else the module.
    if (i <= kQSos) continue;
    if (e.channel >= 0) continue;
    pas_.module_fault = true;
    return;
  }
}

bool NordProfisafeModel::fail_safe_active() const { return passivated(); }

bool NordProfisafeModel::q_cause(int q) const {
  const std::uint8_t* r = requested_.data();
  switch (q) {
    case kQSls:
    case kQSsr:
    case kQSdiP:
    case kQSdiN:
    case kQSos:
      return fn_.tripped(q - kQSls);
    case kQSlsOff:
      return get(r, nin::kSls) && ip_.p820[0] == 0;
    case kQSsrOff:
      return get(r, nin::kSsr) && ip_.p820[1] == 0;
    case kQSdiPOff:
      return get(r, nin::kSdiP) && ip_.p820[2] == 0;
    case kQSdiNOff:
      return get(r, nin::kSdiN) && ip_.p820[3] == 0;
    case kQSosOff:
      return get(r, nin::kSos) && ip_.p820[4] == 0;
    case kQSo1Off:
      return get(r, nin::kOssd1) && ip_.p802[2] == 0;
    case kQSo2Off:
      return get(r, nin::kOssd2) && ip_.p802[3] == 0;
    case kQSo3Off:
      return get(r, nin::kOssd3) && ip_.p802[4] == 0;
    case kQSi1Off:
      return si_[0] && ip_.p802[0] == 0;
    case kQSi2Off:
      return si_[1] && ip_.p802[1] == 0;
    case kQSi1Clock:
    case kQSi2Clock: {
      const int in = q - kQSi1Clock;
      return ip_.p806[in] != 0 && si_[in] && si_source_[in] != ip_.p806[in];
    }
    case kQDiscrepancy:
      return discrepancy_fault_;
    case kQInjected:
      return injected_cause_;
    default:
      return false;
  }
}

// q_cause() of every q error at once, bit i for error i.
inline std::uint32_t NordProfisafeModel::q_causes() {
  // The causes that are a function of the last valid request's F-data
  // alone (P820/P802 are fixed): once per change of those 4 bytes, which
  // stay put while the host's consecutive number counts on.
  const auto req = std::bit_cast<std::uint32_t>(requested_);
  if (req != request_causes_of_) {
    request_causes_of_ = req;
    std::uint32_t rm = 0;
    auto set = [&rm](int q, bool on) { rm |= static_cast<std::uint32_t>(on) << q; };
    const std::uint8_t* r = requested_.data();
    set(kQSlsOff, get(r, nin::kSls) && ip_.p820[0] == 0);
    set(kQSsrOff, get(r, nin::kSsr) && ip_.p820[1] == 0);
    set(kQSdiPOff, get(r, nin::kSdiP) && ip_.p820[2] == 0);
    set(kQSdiNOff, get(r, nin::kSdiN) && ip_.p820[3] == 0);
    set(kQSosOff, get(r, nin::kSos) && ip_.p820[4] == 0);
    set(kQSo1Off, get(r, nin::kOssd1) && ip_.p802[2] == 0);
    set(kQSo2Off, get(r, nin::kOssd2) && ip_.p802[3] == 0);
    set(kQSo3Off, get(r, nin::kOssd3) && ip_.p802[4] == 0);
    request_causes_ = rm;
  }
  static_assert(kQSos - kQSls + 1 == NordSafetyFunctions::kCount);
  return request_causes_ | si_causes_ | static_cast<std::uint32_t>(fn_.trips()) << kQSls |
         static_cast<std::uint32_t>(discrepancy_fault_) << kQDiscrepancy |
         static_cast<std::uint32_t>(injected_cause_) << kQInjected;
}

void NordProfisafeModel::refresh_si_causes() {
  std::uint32_t m = 0;
  auto set = [&m](int q, bool on) { m |= static_cast<std::uint32_t>(on) << q; };
  set(kQSi1Off, si_[0] && ip_.p802[0] == 0);
  set(kQSi2Off, si_[1] && ip_.p802[1] == 0);
  for (int in = 0; in < 2; ++in)
    set(kQSi1Clock + in, ip_.p806[in] != 0 && si_[in] && si_source_[in] != ip_.p806[in]);
  si_causes_ = m;
}

std::uint32_t NordProfisafeModel::q_causes_kept() { return q_causes(); }

std::uint32_t NordProfisafeModel::q_causes_full() const {
  std::uint32_t m = 0;
  for (int i = 0; i < kQCount; ++i) m |= static_cast<std::uint32_t>(q_cause(i)) << i;
  return m;
}

// update_q(), handle_request(), evaluate() and build_response() are inline:
// each has one caller (step(), update_q() evaluate()), which runs them once
// per exchange; as calls they cost their register saves every exchange.
// True when it returned at once (no error active, none with a cause).
inline bool NordProfisafeModel::update_q(TIME now) {
  // Nothing can change while no error is active and none has a cause (the
  // usual step): the loops below would only look.
  const std::uint32_t causes = q_causes();
  if (causes == 0 && active_q_ == 0) return true;
  const std::uint32_t active_before = active_q_;
  for (int i = 0; i < kQCount; ++i) {
    QError& e = q_[i];
    const bool c = (causes >> i) & 1U;
    if (c && !e.active) {
      e.active = true;
      active_q_ |= 1U << i;
      e.onset = now;
      raise_code(e.code);
      if (ip_.p801 == 1 && e.channel >= 0) chan_passive_[e.channel] = true;
    } else if (e.active && !c && now - e.onset >= e.hold &&
               !(e.channel >= 0 && chan_passive_[e.channel])) {
      // A channel error stays latched, code and all, until In 3.7 has
      // acknowledged its channel (spec §2.8 channel passivation).
      e.active = false;
      active_q_ &= ~(1U << i);
      if (p841_ == e.code) {
        p842_ = p841_;
        p841_ = 0;
      }
    }
  }
  if (active_q_ != active_before) refresh_module_fault();
  // A violation's trip ends when its cause is gone (SDI/SOS: at once); the
  // q error then still holds for its 10 s.
  for (int f = 0; f < NordSafetyFunctions::kCount; ++f) {
    if (fn_.tripped(f) && q_[kQSls + f].active && !fn_.cause_present(f, speed_rpm_))
      fn_.clear_trip(f);
  }
  return false;
}

// The head of a PDU (bytes 0..4) as handle_request() and build_response()
// key it: the low 40 bits of its first 8 bytes read little-endian.
namespace {
[[gnu::always_inline]] inline std::uint64_t load_le64(const std::uint8_t* p) {
  std::uint64_t w;
  std::memcpy(&w, p, sizeof w);
  if constexpr (std::endian::native == std::endian::big) w = __builtin_bswap64(w);
  return w;
}
[[gnu::always_inline]] inline void store_le64(std::uint8_t* p, std::uint64_t w) {
  if constexpr (std::endian::native == std::endian::big) w = __builtin_bswap64(w);
  std::memcpy(p, &w, sizeof w);
}
[[gnu::always_inline]] inline void store_le32(std::uint8_t* p, std::uint32_t w) {
  if constexpr (std::endian::native == std::endian::big) w = __builtin_bswap32(w);
  std::memcpy(p, &w, sizeof w);
}
constexpr std::uint64_t kHeadMask = 0xFF'FFFF'FFFFu;
}  // namespace

void NordProfisafeModel::take_head(Crc2Head& h, std::uint64_t key, std::uint16_t seed) {
  // Crc2Cache's head: the seed, the control/status byte, the F-data
  // reversed, then the register run on through 4 zero bytes.
  using Engine = safety::Crc2x24Engine;
  std::uint32_t c = Engine::update_byte(seed, static_cast<std::uint8_t>(key >> 32));
  for (int i = 3; i >= 0; --i)
    c = Engine::update_byte(c, static_cast<std::uint8_t>(key >> (8 * i)));
  for (int j = 0; j < 4; ++j) c = Engine::update_byte(c, 0x00);
  h.key = key;
  h.z4 = c;
}

// True when it accepted a valid new request without R_cons_nr.
inline bool NordProfisafeModel::handle_request(TIME now, std::span<const std::uint8_t> in) {
  if (in.size() < kPdu) return false;
  std::uint64_t w = load_le64(in.data());  // the request, byte i in bits 8i..8i+7
  // Not a new telegram: nothing is injected into it (the injections count
  // new ones only) and its toggle stays the last one, so it is ignored.
  if (((w >> 32 & cb::kToggleH) != 0) == last_toggle_) return false;
  if (injecting_ && (repeat_req_ > 0 || corrupt_req_n_ > 0)) [[unlikely]] {
    std::array<std::uint8_t, kPdu> req;
    store_le64(req.data(), w);
    if (repeat_req_ > 0) {
      req = req_hist_[1];  // the request received two exchanges earlier
      --repeat_req_;
    }
    if (corrupt_req_n_ > 0) {
      req[corrupt_req_byte_] ^= corrupt_req_mask_;
      --corrupt_req_n_;
    }
    w = load_le64(req.data());
    if (((req[4] & cb::kToggleH) != 0) == last_toggle_) return false;  // not a new telegram now
  }
  const auto control = static_cast<std::uint8_t>(w >> 32);
  last_toggle_ = (control & cb::kToggleH) != 0;
  req_hist_[1] = req_hist_[0];
  store_le64(req_hist_[0].data(), w);

  const bool rcons = (control & cb::kRConsNr) != 0;
  const std::uint32_t expected = rcons ? 0u : safety::next_cons_nr(cn_);
  // check_pdu(req, 4, expected, crc1_) (an 8-byte PDU, F-data of 4): the
  // received CRC2 is bytes 5..7, most significant first.
  const std::uint32_t got = static_cast<std::uint32_t>(__builtin_bswap64(w)) & 0xFFFFFFu;
  tail_ = crc2_tail(expected);
  const bool ok = (crc2_z4(req_head_[last_toggle_], w & kHeadMask) ^ tail_) == got;
  cn_ = expected;  // the host counts on as well, valid or not
  cons_nr_r_ = false;
  respond_pending_ = true;
  if (!ok) {
    pas_.ce_crc = true;
    pas_.fault_fv = true;
    ++crc_errors_;
    return false;
  }
  t_valid_ = now;
  if (rcons) {
    pas_.ce_crc = pas_.wd_timeout = false;
    cons_nr_r_ = true;
  }
  pas_.host_fv = (control & cb::kActivateFv) != 0;
  const auto data = static_cast<std::uint32_t>(w);  // bytes 0..3
  store_le32(requested_.data(), data);
  Accepted& a = accepted_[accepted_head_++ % kHist];
  a.cn = cn_;
  store_le32(a.data.data(), data);
  if ((control & cb::kOaReq) && !pas_.ce_crc && !pas_.wd_timeout && !module_fault() &&
      fatal_code_ == 0)
    pas_.fault_fv = false;
  // Channel-passivation acknowledge In 3.7 (rising edge, cause gone).
  const bool ack = get(requested_.data(), nin::kChannelAck);
  if (ack && !chan_ack_prev_) {
    for (int ch = 0; ch < 3; ++ch) {
      bool cause = false;
      for (int i = 0; i < kQCount; ++i) {
        const QError& e = q_[i];
        if (e.active && e.channel == ch && (q_cause(i) || now - e.onset < e.hold)) cause = true;
      }
      if (!cause) chan_passive_[ch] = false;
    }
    at_rest_ = steady_ = false;  // chan_passive_ may have changed
  }
  chan_ack_prev_ = ack;
  return !rcons;
}

// evaluate()'s P805 input filter when an input differs from its filtered
// level: a new level counts once it has been stable for P805.
void NordProfisafeModel::filter_si(TIME now) {
  for (int i = 0; i < 2; ++i) {
    if (si_raw_[i] == si_[i]) {
      si_changing_[i] = false;
      continue;
    }
    if (!si_changing_[i]) {
      si_changing_[i] = true;
      si_change_since_[i] = now;
    }
    if (now - si_change_since_[i] >= std::chrono::milliseconds(ip_.p805_ms)) {
      si_[i] = si_raw_[i];
      refresh_si_causes();
      si_changing_[i] = false;
    }
  }
}

[[gnu::always_inline]] inline void NordProfisafeModel::evaluate(TIME now, TIME dt) {
  if (!pas_.no_fpar && now - t_valid_ > wd_ && !pas_.wd_timeout) {
    pas_.wd_timeout = true;
    pas_.fault_fv = true;
    ++wd_expiries_;
  }
  // At rest (at_rest_) with pas_ and requested_ as that evaluate() left
  // them: the rest would write back what is there.
  if (at_rest_ && pas_word() == rest_pas_ && std::bit_cast<std::uint32_t>(requested_) == rest_req_)
    return;
  resp_fresh_ = false;  // what build_response() keeps may change now
  // Input filter P805: a new level counts once it has been stable for P805.
  // Both inputs at their filtered level (the usual step):
  // filter_si() would only clear si_changing_, so that is done for both
  // at once.
  static_assert(sizeof si_raw_ == 2 && sizeof si_ == 2 && sizeof si_changing_ == 2);
  std::uint16_t raw2, si2;
  std::memcpy(&raw2, si_raw_.data(), 2);
  std::memcpy(&si2, si_.data(), 2);
  if (raw2 == si2) {
    si_changing_ = {};
  } else {
    filter_si(now);
  }
  // Dual-channel SI1/SI2 discrepancy (P800[-01] = 1): both must agree within
  // P803; the error clears when both channels are off (spec §4.5 [AMBIG]).
  if (ip_.p800[0] == 1) {
    if (si_[0] != si_[1]) {
      if (!discrepancy_timing_) {
        discrepancy_timing_ = true;
        discrepancy_since_ = now;
      }
      if (now - discrepancy_since_ > std::chrono::milliseconds(ip_.p803_ms))
        discrepancy_fault_ = true;
    } else {
      discrepancy_timing_ = false;
      if (!si_[0] && !si_[1]) discrepancy_fault_ = false;
    }
  }

  if (passivated()) {
    applied_ = {};
  } else {
    applied_ = requested_;
  }
  const std::uint8_t* a = applied_.data();
  // fn_ reads the request only for a function P820 enables: with none, it
  // gets the empty one, a constant (not built on the stack every step).
  if (fn_.any_enabled()) {
    NordSafetyFunctions::Request rq;
    rq.on = {get(a, nin::kSls), get(a, nin::kSsr), get(a, nin::kSdiP), get(a, nin::kSdiN),
             get(a, nin::kSos)};
    rq.sls_level =
        static_cast<std::uint8_t>((get(a, nin::kSlsLevel1) << 1) | get(a, nin::kSlsLevel0));
    fn_.step(now, dt, rq, speed_rpm_, position_inc_);
  } else {
    static constexpr NordSafetyFunctions::Request kNone{};
    fn_.step(now, dt, kNone, speed_rpm_, position_inc_);
  }
  const bool q_idle = update_q(now);
  if (fatal_code_ != 0 || module_fault()) pas_.fault_fv = true;
  {
    std::uint16_t raw_now, si_now;
    std::memcpy(&raw_now, si_raw_.data(), 2);
    std::memcpy(&si_now, si_.data(), 2);
    at_rest_ = rest_skip_ && q_idle && raw_now == si_now &&
               (ip_.p800[0] != 1 || si_[0] == si_[1]) && fn_.at_rest();
    rest_pas_ = pas_word();
    rest_req_ = std::bit_cast<std::uint32_t>(requested_);
  }

  if (passivated()) {  // every SO off, whatever the (already 0) request says
    ossd_ = {};
    return;
  }
  // ossd_full() by table: the requests pick the entry, a passive channel
  // clears its byte (bools are bytes 0/1, so ~passive keeps or clears bit 0;
  // byte 3 is 0 in the table).
  static_assert(nin::kOssd1.byte == 0 && nin::kOssd1.bit == 0 && nin::kOssd2.byte == 3 &&
                nin::kOssd2.bit == 0 && nin::kOssd3.byte == 3 && nin::kOssd3.bit == 1);
  const unsigned so = (a[0] & 1u) | (a[3] & 3u) << 1;
  std::uint32_t passive = 0;
  std::memcpy(&passive, chan_passive_.data(), chan_passive_.size());
  const std::uint32_t on = ossd_of_[so] & ~passive;
  std::memcpy(ossd_.data(), &on, ossd_.size());
}

std::array<bool, 3> NordProfisafeModel::ossd_full() const {
  std::array<bool, 3> o{};
  if (passivated()) return o;
  const std::uint8_t* a = applied_.data();
  bool cmd[3] = {get(a, nin::kOssd1), get(a, nin::kOssd2), get(a, nin::kOssd3)};
  if (ip_.p800[1] == 1) cmd[0] = cmd[1] = cmd[0] && cmd[1];  // SO1+SO2 dual channel
  for (int i = 0; i < 3; ++i) o[i] = cmd[i] && ip_.p802[2 + i] == 1 && !chan_passive_[i];
  return o;
}

std::array<std::uint8_t, 4> NordProfisafeModel::response_data_full() const {
  std::array<std::uint8_t, 4> data{};
  if (!passivated()) {  // fail-safe values are all 0 (spec §2.4)
    std::uint8_t* d = data.data();
    const std::uint8_t* a = applied_.data();
    put(d, nout::kOssd1Off, !ossd_[0]);
    put(d, nout::kOssd2Off, !ossd_[1]);
    put(d, nout::kOssd3Off, !ossd_[2]);
    put(d, nout::kClock1Off, ip_.p802[5] != 1);
    put(d, nout::kClock2Off, ip_.p802[6] != 1);
    put(d, nout::kSosOk, fn_.ok(NordSafetyFunctions::kSos));
    put(d, nout::kSlsOk, fn_.ok(NordSafetyFunctions::kSls));
    put(d, nout::kSlsLevel0, get(a, nin::kSlsLevel0));
    put(d, nout::kSlsLevel1, get(a, nin::kSlsLevel1));
    put(d, nout::kSdiPOk, fn_.ok(NordSafetyFunctions::kSdiP));
    put(d, nout::kSdiNOk, fn_.ok(NordSafetyFunctions::kSdiN));
    put(d, nout::kSsm, fn_.ssm());
    put(d, nout::kSi1, si_[0] && ip_.p802[0] == 1);
    put(d, nout::kSi2, si_[1] && ip_.p802[1] == 1);
    put(d, nout::kSsrOk, fn_.ok(NordSafetyFunctions::kSsr));
  }
  return data;
}

// What response_data_full() reads besides the i-parameters (fixed) and
// passivated() (all 0 then): the functions' status bits, SI1/SI2, SO1-3 and
// the request's SLS level bits, byte by byte in two words.
[[gnu::always_inline]] inline std::array<std::uint8_t, 4> NordProfisafeModel::data_now() {
  if (passivated()) return {};  // fail-safe values are all 0 (spec §2.4)
  std::uint16_t si;
  std::memcpy(&si, si_.data(), sizeof si);
  std::uint32_t so = 0;
  std::memcpy(&so, ossd_.data(), ossd_.size());
  const std::uint64_t k0 = fn_.status_key() | static_cast<std::uint64_t>(si) << 48;
  const std::uint64_t k1 = so | static_cast<std::uint64_t>(applied_[1]) << 32;
  if (k0 != data_key_[0] || k1 != data_key_[1]) {
    data_key_[0] = k0;
    data_key_[1] = k1;
    data_kept_ = response_data_full();
  }
  return data_kept_;
}

std::array<std::uint8_t, 4> NordProfisafeModel::response_data() { return data_now(); }

[[gnu::always_inline]] inline void NordProfisafeModel::build_response() {
  // The F-data and the status bits given by pas_ and the faults, once per
  // full evaluate() (resp_fresh_): a step skipped at rest changed nothing
  // they are made of.
  if (!resp_fresh_) {
    resp_data_ = data_now();
    std::uint8_t st = 0;
    if (pas_.ce_crc) st |= sbit::kCeCrc;
    if (pas_.wd_timeout) st |= sbit::kWdTimeout;
    if (device_fault()) st |= sbit::kDeviceFault;
    if (passivated()) st |= sbit::kFvActivated;
    resp_status_ = st;
    resp_fresh_ = rest_skip_;  // a twin without the skip (tests) computes them every time
  }
  const std::array<std::uint8_t, 4> data = resp_data_;
  std::uint8_t status = resp_status_;
  if (last_toggle_) status |= sbit::kToggleD;
  if (cons_nr_r_) status |= sbit::kConsNrR;

  // The frame is written in its place on the channel (nothing else uses
  // the channel before the end of this function; step() delivers next).
  NordResponseChannel::Frame& frame = channel_.push_delivered(now_);
  NordFrameTag& tag = frame.tag;
  tag.id = ++frames_sent_;
  tag.sent = tag.produced = now_;
  tag.data = data;
  tag.corrupted = tag.foreign = tag.repeated = false;
  // write_pdu(pdu_, data, status, cn_, crc1_): the head's Z4 and the
  // number's TAIL (handle_request() looked it up for cn_), the PDU as one
  // word: F-data, status byte, CRC2 most significant first.
  std::uint64_t head;
  {
    std::uint32_t d;
    std::memcpy(&d, data.data(), 4);
    if constexpr (std::endian::native == std::endian::big) d = __builtin_bswap32(d);
    head = d | static_cast<std::uint64_t>(status) << 32;
  }
  std::uint32_t crc;
  if (injecting_ && foreign_ > 0) [[unlikely]] {
    // Another F-device's CRC1 as the seed: computed in full.
    crc = safety::compute_crc2(data, status, cn_, static_cast<std::uint16_t>(crc1_ ^ 0x5A5Au));
    --foreign_;
    tag.foreign = true;
  } else {
    crc = crc2_z4(resp_head_[last_toggle_], head) ^ tail_;
  }
  // CRC2 (24 bits: the engine masks every step, and so Z4 and TAIL) most
  // significant first in bytes 5..7: its three bytes byte-reversed into
  // the top of the word.
  // The word is written to the PDU, the history and (no injection) the
  // frame from the register, not read back from pdu_.
  const std::uint64_t word = head | __builtin_bswap64(crc);
  store_le64(pdu_.data(), word);
  Sent& s = sent_[sent_head_++ % kHist];
  s.produced = now_;
  store_le64(s.pdu.data(), word);
  if (injecting_) [[unlikely]] {
    if (repeat_resp_ > 0 && sent_head_ >= 3) {
      const Sent& old = sent_[(sent_head_ - 3) % kHist];  // two exchanges earlier
      pdu_ = old.pdu;
      tag.produced = old.produced;
      std::copy_n(old.pdu.begin(), 4, tag.data.begin());
      tag.repeated = true;
      --repeat_resp_;
    }
    if (corrupt_resp_n_ > 0) {
      pdu_[corrupt_resp_byte_] ^= corrupt_resp_mask_;
      --corrupt_resp_n_;
      tag.corrupted = true;
    }
    frame.pdu = pdu_;
    return;
  }
  store_le64(frame.pdu.data(), word);
}

// The full step() for a request that repeats the last accepted one but
// for Toggle_h, the consecutive number and CRC2 (steady_, see the header),
// or false with nothing written (but crc2_tail()'s kept high part, which
// the full path takes alike). The CRC2 heads' Z4 are those kept when it
// armed (steady_z4_). What the full path would do, part by part:
//  * handle_request(): no injection (injecting_ clear), a new telegram
//    (Toggle_h flipped), no R_cons_nr, CRC2 checked for next_cons_nr(cn_)
//    as there. Accepted: the same F-data (requested_, chan_ack_prev_ and
//    the channel-acknowledge edge unchanged), the same Activate_FV
//    (host_fv unchanged), cons_nr_R already clear; OA_Req finds ce_crc,
//    wd_timeout, the module fault and the fatal code as the arming step's
//    handle_request() did (only handle_request() on an error or
//    R_cons_nr, evaluate() in full or calls that clear at_rest_ change
//    them), so fault_fv stays as it left it.
//  * evaluate(): the watchdog runs from now (t_valid_ = now) and pas_ and
//    requested_ are as the last evaluate() left them at rest: skipped.
//  * build_response(): the kept F-data and status (resp_fresh_), Toggle_d
//    = Toggle_h, no foreign injection.
inline bool NordProfisafeModel::step_steady(TIME now, const std::uint8_t* in, std::uint8_t* out) {
  const std::uint64_t w = load_le64(in);
  const std::uint64_t head = w & kHeadMask;
  const bool t = !last_toggle_;
  if (head != steady_req_[t]) return false;
  // A frame that arrives at once (push_delivered()'s direct case; else
  // push()).
  if (!channel_.direct(now)) return false;
  const std::uint32_t expected = safety::next_cons_nr(cn_);
  const std::uint32_t tail = crc2_tail(expected);
  const std::uint32_t got = static_cast<std::uint32_t>(__builtin_bswap64(w)) & 0xFFFFFFu;
  if ((steady_z4_[t][0] ^ tail) != got) return false;  // the full path counts it
  last_toggle_ = t;
  req_hist_[1] = req_hist_[0];
  store_le64(req_hist_[0].data(), w);
  tail_ = tail;
  cn_ = expected;
  t_valid_ = now;
  Accepted& a = accepted_[accepted_head_++ % kHist];
  a.cn = expected;
  store_le32(a.data.data(), static_cast<std::uint32_t>(w));

  NordResponseChannel::Frame& frame = channel_.push_direct(now);
  NordFrameTag& tag = frame.tag;
  tag.id = ++frames_sent_;
  tag.sent = tag.produced = now;
  tag.data = resp_data_;
  tag.corrupted = tag.foreign = tag.repeated = false;
  const std::uint64_t rhead = steady_resp_[t];
  const std::uint32_t crc = steady_z4_[t][1] ^ tail;
  const std::uint64_t word = rhead | __builtin_bswap64(crc);
  store_le64(pdu_.data(), word);
  Sent& s = sent_[sent_head_++ % kHist];
  s.produced = now;
  store_le64(s.pdu.data(), word);
  store_le64(frame.pdu.data(), word);
  channel_.deliver(now);
  std::copy_n(channel_.shown().begin(), kPdu, out);
  ++steady_steps_;
  return true;
}

void NordProfisafeModel::step(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
                              std::span<std::uint8_t> to_plc) {
  now_ = now;
  // revs_per_s * pulses * dt, as (speed / 60 / P811 * pulses) * dt, when
  // it can change the position (integrate_).
  if (integrate_) position_inc_ += inc_per_s_ * std::chrono::duration<double>(dt).count();
  // The steady exchange (armed: pas_.no_fpar is clear, see step_steady();
  // every call that clears at_rest_, sets an injection or drops requests
  // disarms it, so no drop waits to start). A leaf without calls; the rest
  // as a tail call.
  if (steady_ && from_plc.size() >= kPdu && to_plc.size() >= kPdu &&
      step_steady(now, from_plc.data(), to_plc.data()))
    return;
  step_full(now, dt, from_plc, to_plc);
}

void NordProfisafeModel::step_full(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
                                   std::span<std::uint8_t> to_plc) {
  if (drop_start_pending_) {
    drop_until_ = now + drop_for_;
    drop_start_pending_ = false;
  }
  const bool accepted = !pas_.no_fpar && now >= drop_until_ && handle_request(now, from_plc);
  evaluate(now, dt);
  if (respond_pending_) {
    build_response();
    respond_pending_ = false;
  }
  steady_ = accepted && steady_allowed_ && !injecting_ && at_rest_ && resp_fresh_;
  if (steady_) {
    // The request just accepted (toggle last_toggle_) and, for the other
    // toggle value, the same with Toggle_h flipped.
    const std::uint64_t h = load_le64(req_hist_[0].data()) & kHeadMask;
    steady_req_[last_toggle_] = h;
    steady_req_[!last_toggle_] = h ^ static_cast<std::uint64_t>(cb::kToggleH) << 32;
    std::uint32_t d;  // as build_response() makes the head
    std::memcpy(&d, resp_data_.data(), 4);
    if constexpr (std::endian::native == std::endian::big) d = __builtin_bswap32(d);
    const std::uint64_t base = d | static_cast<std::uint64_t>(resp_status_) << 32;
    steady_resp_[0] = base;
    steady_resp_[1] = base | static_cast<std::uint64_t>(sbit::kToggleD) << 32;
    // Their Z4 as the full path takes them (kept heads; crc1_ changes only
    // through set_crc1(), which disarms).
    for (int k = 0; k < 2; ++k) {
      steady_z4_[k][0] = crc2_z4(req_head_[k], steady_req_[k]);
      steady_z4_[k][1] = crc2_z4(resp_head_[k], steady_resp_[k]);
    }
  }
  channel_.deliver(now);
  if (to_plc.size() >= kPdu) {  // the usual buffer: a constant size, copied inline
    std::copy_n(channel_.shown().begin(), kPdu, to_plc.begin());
  } else {
    std::copy_n(channel_.shown().begin(), to_plc.size(), to_plc.begin());
  }
}

io::RecordError NordProfisafeModel::read_record(std::uint16_t index, std::span<std::uint8_t> out,
                                                std::size_t& length) {
  length = 0;
  if (index != safety::kNordDiagRecordIndex) return io::RecordError::InvalidIndex;
  if (out.size() < 4) return io::RecordError::InvalidLength;
  out[0] = static_cast<std::uint8_t>(p841_ >> 8);
  out[1] = static_cast<std::uint8_t>(p841_);
  out[2] = static_cast<std::uint8_t>(p842_ >> 8);
  out[3] = static_cast<std::uint8_t>(p842_);
  length = 4;
  if (out.size() >= 6) {
    out[4] = static_cast<std::uint8_t>(code_events_ >> 8);
    out[5] = static_cast<std::uint8_t>(code_events_);
    length = 6;
  }
  return io::RecordError::None;
}

io::RecordError NordProfisafeModel::write_record(std::uint16_t index,
                                                 std::span<const std::uint8_t> data) {
  if (index != safety::kFParamRecordIndex) return io::RecordError::InvalidIndex;
  at_rest_ = steady_ = false;  // a block, accepted or refused, may change what evaluate() reads
  auto refuse = [this](std::uint16_t code) {
    pas_.no_fpar = true;
    raise_code(code);
    return static_cast<io::RecordError>(code);
  };
  // Without a valid F-address (fatal 5726 at power-on) there is nothing to
  // compare F_Dest_Add with: the write is refused with 5726 itself, so the
  // F-host reports the address fault by its own number (spec §5.5, §8.3),
  // not as a 5711 that would also push 5726 out of P841.
  if (!address_valid_) return refuse(err::kDipRead);
  if (data.size() != safety::kFParamBlockSize) {
    if (fatal_code_ == 0) fatal_code_ = err::kParTelegram;  // 5725 is fatal
    return refuse(err::kParTelegram);
  }
  std::span<const std::uint8_t, safety::kFParamBlockSize> block(data.data(),
                                                                safety::kFParamBlockSize);
  const safety::FParameters p = safety::decode(block);
  if (safety::compute_crc1(block) != p.par_crc) return refuse(err::kParCrc);
  if (p.par_version != 1) return refuse(err::kParVersion);
  if (p.crc_length != 0) return refuse(err::kCrcLength);
  if (p.block_id != 1 || p.check_ipar || (data[0] & 0xC0) || (data[1] & 0x07) ||
      p.wd_time_ms > 10000)
    return refuse(err::kParGeneral);
  if (safety::sil_level(p.sil) > max_sil_) return refuse(err::kSilTooHigh);
  if (p.source_add == 0 || p.source_add == 65535) return refuse(err::kSourceInvalid);
  if (p.dest_add == 0 || p.dest_add > 255) return refuse(err::kDestInvalid);
  if (p.dest_add != f_address_) return refuse(err::kDestMismatch);
  if (p.wd_time_ms == 0) return refuse(err::kWatchdogZero);
  if (p.ipar_crc != ip_.p840) return refuse(err::kIparCrc);

  pas_.no_fpar = false;
  set_crc1(p.par_crc);
  wd_ = std::chrono::milliseconds(p.wd_time_ms);
  cn_ = 0;
  last_toggle_ = false;
  pas_.ce_crc = pas_.wd_timeout = cons_nr_r_ = false;
  pas_.fault_fv = pas_.host_fv = true;
  t_valid_ = now_;
  requested_ = {};
  if (p841_ >= err::kDestMismatch && p841_ <= err::kCrcLength) {
    p842_ = p841_;
    p841_ = 0;
  }
  return io::RecordError::None;
}

namespace {
// Newest entry with number cn in a history ring.
template <class Ring>
bool find_newest(const Ring& ring, std::size_t head, std::uint32_t cn,
                 std::span<std::uint8_t, 4> out) {
  for (std::size_t i = 1; i <= ring.size() && i <= head; ++i) {
    const auto& s = ring[(head - i) % ring.size()];
    if (s.cn == cn) {
      std::copy(s.data.begin(), s.data.end(), out.begin());
      return true;
    }
  }
  return false;
}
}  // namespace

bool NordProfisafeModel::same_exchange_state(const NordProfisafeModel& o) const {
  auto key = [](const NordProfisafeModel& m) {
    return std::tie(m.last_toggle_, m.cn_, m.cons_nr_r_, m.t_valid_, m.requested_, m.applied_,
                    m.chan_ack_prev_, m.tail_, m.frames_sent_, m.pdu_, m.sent_head_,
                    m.accepted_head_, m.req_hist_, m.at_rest_, m.rest_req_, m.rest_pas_,
                    m.resp_fresh_, m.resp_status_, m.resp_data_, m.respond_pending_, m.ossd_,
                    m.crc_errors_, m.wd_expiries_, m.p841_, m.p842_, m.active_q_);
  };
  if (key(*this) != key(o) || pas_word() != o.pas_word()) return false;
  for (std::size_t i = 0; i < kHist; ++i) {
    if (sent_[i].produced != o.sent_[i].produced || sent_[i].pdu != o.sent_[i].pdu) return false;
    if (accepted_[i].cn != o.accepted_[i].cn || accepted_[i].data != o.accepted_[i].data)
      return false;
  }
  const NordFrameTag &a = channel_.shown_tag(), &b = o.channel_.shown_tag();
  return channel_.shown() == o.channel_.shown() && channel_.in_flight() == o.channel_.in_flight() &&
         std::tie(a.id, a.sent, a.produced, a.data, a.corrupted, a.foreign, a.repeated) ==
             std::tie(b.id, b.sent, b.produced, b.data, b.corrupted, b.foreign, b.repeated);
}

bool NordProfisafeModel::accepted_request(std::uint32_t cn, std::span<std::uint8_t, 4> out) const {
  return find_newest(accepted_, accepted_head_, cn, out);
}

PLC_REGISTER_DEVICE_MODEL("nord_profisafe", NordProfisafeModel)

}  // namespace plc::sim

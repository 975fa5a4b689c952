#include "pr5510/pr5510_model.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "pr5510/display_rounding.hpp"

namespace plc::sim {

using namespace std::chrono_literals;
namespace wg = plc::weighing;

namespace {
constexpr TIME kCycle = std::chrono::milliseconds(wg::kDeviceCycleMs);
}

Pr5510Model::Pr5510Model(const Pr5510Config& c) : cfg_(c), process_(c.filling) {
  digits_per_kg_ = std::pow(10.0, cfg_.decimals);
  fsd_digits_ = static_cast<DINT>(std::lround(cfg_.full_scale * digits_per_kg_));
  overload_digits_ = static_cast<DINT>(std::lround(cfg_.overload * digits_per_kg_));
  filtered_kg_ = cfg_.filling.initial_load;
  filter_alpha_ = std::min(1.0, 1e-3 / std::chrono::duration<double>(cfg_.filter_time).count());
  power_cycle();
}

void Pr5510Model::set_input(int n, bool on) {
  if (n >= 1 && n <= 3) inputs_[static_cast<std::size_t>(n - 1)] = on;
}

void Pr5510Model::power_cycle() {
  // Spec §7.1: Power_Fail and Cal_Changed are set at power-on. Tare, test
  // mode, outputs and the window handshake are volatile; zero is kept.
  st_ = {};
  st_.PowerFail = true;
  st_.CalChanged = true;
  tare_ = 0;
  pending_ = Pending::None;
  calibrating_ = false;  // the calibration itself is kept (EAROM, spec §1)
  write_in_progress_ = false;
  outputs_ = 0;
  rd_.fill(0);
  // A code or command bit still set from before the restart must first go
  // back to 0: only a fresh 0 -> 1 change triggers.
  prev_w5_ = 0xFF;
  prev_w7_ = 0xFF;
  since_cycle_ = 0ns;
}

void Pr5510Model::io_connection_lost() {
  master_lost_ = true;
  outputs_ = 0;  // the valves close now, not at the next cycle
  st_.Out1 = st_.Out2 = st_.Out3 = false;
}

// A host that calls step() delivers the outputs every cycle (the sim plugin,
// the PROFINET device once its AR is up again): each step is a new message.
void Pr5510Model::step(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
                       std::span<std::uint8_t> to_plc) {
  step_io(now, dt, from_plc, true, to_plc);
}

void Pr5510Model::step_io(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
                          bool new_message, std::span<std::uint8_t> to_plc) {
  if (new_message) master_lost_ = false;  // a master again: its outputs count
  since_cycle_ += dt;                     // the ms ticks do not read it
  // The usual step (19 of 20): 1 ms with no ms left over (since_ms_ 0 ->
  // 1 ms -> one tick -> 0, so it is not written), no device cycle due, and
  // the read window copied as it is (only device_cycle() and power_cycle()
  // write it), then the one tick as a tail call. A leaf: everything else
  // (the loop of ticks, the cycle, the zeroed window) is step_other().
  if (dt == 1ms && since_ms_ == 0ns && since_cycle_ < kCycle && to_plc.size() >= wg::kWindowSize &&
      cfg_.scale_interface) {
    // std::memcpy of the constant size: inline (std::copy called memmove).
    std::memcpy(to_plc.data(), rd_.data(), rd_.size());
    tick_1ms();
    return;
  }
  step_other(now, dt, from_plc, to_plc);
}

// step_io() but the usual step, as it was before that shortcut: since_ms_
// counts the ms to tick, since_cycle_ (already advanced) the device cycle.
// It takes step()'s arguments (now unused), so step()'s tail call passes
// them where they are.
void Pr5510Model::step_other(TIME, TIME dt, std::span<const std::uint8_t> from_plc,
                             std::span<std::uint8_t> to_plc) {
  since_ms_ += dt;
  if (since_cycle_ < kCycle) {
    // No device cycle in this step: the read window stays as it is through
    // the ticks, so it is handed over first.
    put_read_window(to_plc);
    while (since_ms_ >= 1ms) {
      since_ms_ -= 1ms;
      tick_1ms();
    }
    return;
  }
  step_with_cycle(from_plc, to_plc);
}

// step_io() with a device cycle due: the ticks, then the cycle(s), then
// the read window. Out of line, so the usual step keeps nothing across its
// calls.
void Pr5510Model::step_with_cycle(std::span<const std::uint8_t> from_plc,
                                  std::span<std::uint8_t> to_plc) {
  while (since_ms_ >= 1ms) {
    since_ms_ -= 1ms;
    tick_1ms();
  }
  while (since_cycle_ >= kCycle) {
    since_cycle_ -= kCycle;
    if (cfg_.scale_interface && from_plc.size() >= wg::kWindowSize) device_cycle(from_plc);
  }
  put_read_window(to_plc);
}

void Pr5510Model::put_read_window(std::span<std::uint8_t> to_plc) const {
  if (to_plc.size() >= wg::kWindowSize) {
    if (cfg_.scale_interface) {
      // std::memcpy of the constant size: inline (std::copy called memmove).
      std::memcpy(to_plc.data(), rd_.data(), rd_.size());
    } else {
      std::fill(to_plc.begin(), to_plc.end(), std::uint8_t{0});
    }
  }
}

// One ms of the process and the filter, out of line: step_io() then keeps
// nothing across the noise's libm calls (no spills of its spans). Every
// other ms the noise gives the spare of its pair: then the tick is a leaf
// (no frame); the draw of a pair, with its libm calls, is filter_drawn()
// (a tail call), which reads the process's load and landing rate after
// them from memory.
void Pr5510Model::tick_1ms() {
  process_.step_1ms(outputs_ & 1U, outputs_ & 2U, outputs_ & 4U);
  if (process_.noise_spare()) {
    filtered_kg_ += (process_.measured_spare() - filtered_kg_) * filter_alpha_;
    return;
  }
  filter_drawn();
}

void Pr5510Model::filter_drawn() {
  filtered_kg_ += (process_.measured_drawn() - filtered_kg_) * filter_alpha_;
}

void Pr5510Model::device_cycle(std::span<const std::uint8_t> w) {
  ++cycles_;
  update_weight_and_status();

  // W[6]: outputs 1-3 are levels; they drive the valves from this cycle on.
  // With the master lost they stay off (io_connection_lost).
  outputs_ = master_lost_ ? 0 : w[wg::w::kOutputs] & 0x07;
  st_.Out1 = outputs_ & 1U;
  st_.Out2 = outputs_ & 2U;
  st_.Out3 = outputs_ & 4U;

  // W[7]: each function acts on the 0->1 edge between two samples (§3.3).
  const std::uint8_t w7 = w[wg::w::kCommands];
  const auto rising = static_cast<std::uint8_t>(w7 & ~prev_w7_);
  prev_w7_ = w7;
  // The rising command bits in ascending order, as a loop over the bits
  // would take them (usually none: no loop at all).
  static_assert(wg::kCommandBitCount < 8);
  for (unsigned r = rising & ((1U << wg::kCommandBitCount) - 1U); r != 0; r &= r - 1U)
    start_command(static_cast<wg::CommandBit>(std::countr_zero(r)));

  // W[5]: a change 0 -> code while Write_Active = 0 starts one write (§7.1).
  const std::uint8_t w5 = w[wg::w::kWriteValueSelect];
  if (w5 == 0) {
    st_.WriteActive = false;     // the master has seen the acknowledgement
    write_in_progress_ = false;  // a master that gives up gets no late ack
  } else if (prev_w5_ == 0 && !st_.WriteActive) {
    accept_write(w5, io::load<std::uint32_t>(w.data() + wg::w::kValue, wg::byte_order(cfg_.bus)));
  }
  prev_w5_ = w5;

  run_pending();
  serve_read(w[wg::w::kReadValueSelect]);
  wg::encode_status(st_, rd_);
}

void Pr5510Model::update_weight_and_status() {
  const double kg =
      st_.TestActive ? cfg_.test_value : (filtered_kg_ - zero_offset_kg_) * span_gain_;
  const double exact = kg * digits_per_kg_;
  const double d = std::max<double>(1.0, cfg_.division);
  // What the display can show: weights beyond it (a steep span calibration,
  // a huge test value) saturate, so every value and every difference of two
  // (net = gross - tare, the standstill check) fits a DINT.
  constexpr double kDisplayMax = 999'999'999.0;
  // std::round and std::llround, inline (display_rounding.hpp).
  const double shown = pr5510_rounding::round(exact / d) * d;
  gross_ = std::isnan(shown) ? 0 : static_cast<DINT>(std::clamp(shown, -kDisplayMax, kDisplayMax));
  gross100_ = std::isnan(exact)
                  ? 0
                  : pr5510_rounding::llround(std::clamp(exact, -kDisplayMax, kDisplayMax) * 100.0);

  // Standstill: the displayed weight stays within +- range for the time.
  if (std::abs(gross_ - still_ref_) <= cfg_.standstill_range) {
    still_for_ += kCycle;
  } else {
    still_ref_ = gross_;
    still_for_ = 0ns;
  }
  st_.StandStill = still_for_ >= cfg_.standstill_time;

  const DINT fsd = fsd_digits();
  const bool above = gross_ >= fsd;
  if (above && !st_.AboveFsd) last_error_ = wg::device_error::kOverFullScale;
  st_.AboveFsd = above;
  st_.Overload = gross_ >= fsd + overload_digits_;
  st_.BelowZero = exact <= -0.25 * d;
  st_.CenterZero = std::abs(exact) <= 0.25 * d;
  st_.Dimmed = st_.AboveFsd || st_.BelowZero;
  st_.InsideZsr = std::abs(filtered_kg_) <= cfg_.zero_range;
  st_.AduError = adu_error_;
  st_.Inp1 = inputs_[0];
  st_.Inp2 = inputs_[1];
  st_.Inp3 = inputs_[2];
  const DINT net = gross_ - tare_;
  st_.Limit1 = limit_set_[0] && net >= limit_[0];
  st_.Limit2 = limit_set_[1] && net >= limit_[1];
  st_.Limit3 = limit_set_[2] && net >= limit_[2];
}

void Pr5510Model::start_command(wg::CommandBit c) {
  ++commands_accepted_;
  if (pending_ != Pending::None) {
    // One command at a time: a second one while tare/zero waits fails
    // with "taring was active" (error 46).
    st_.CmdError = true;
    last_error_ = wg::device_error::kTaringActive;
    return;
  }
  st_.CmdError = false;  // cleared by the next accepted command ([INFERRED])
  if (calibrating_ && (c == wg::CommandBit::SetZero || c == wg::CommandBit::SetTare)) {
    finish_command(wg::device_error::kCalInProgress);
    return;
  }
  switch (c) {
    case wg::CommandBit::SetZero:
      pending_ = Pending::Zero;
      break;
    case wg::CommandBit::SetTare:
      if (cfg_.legal_for_trade && gross_ < 0) {
        finish_command(wg::device_error::kTareNegativeWm);
        return;
      }
      pending_ = Pending::Tare;
      break;
    case wg::CommandBit::ResTare:
      tare_ = 0;
      st_.TareActive = false;
      break;
    case wg::CommandBit::SetTest:
      st_.TestActive = true;
      break;
    case wg::CommandBit::ResTest:
      st_.TestActive = false;
      break;
    case wg::CommandBit::ResPower:
      st_.PowerFail = false;
      break;
  }
  if (pending_ != Pending::None) {
    st_.CmdBusy = true;  // device_cycle() runs it in this same cycle
    pending_for_ = 0ns;
  } else {
    finish_command(wg::device_error::kNone);
  }
}

bool Pr5510Model::panel_start_calibration() {
  if (cfg_.cal_switch_locked) {
    last_error_ = wg::device_error::kCalSwitchLocked;
    return false;
  }
  if (pending_ != Pending::None) {
    last_error_ = wg::device_error::kTaringActive;
    return false;
  }
  calibrating_ = true;
  return true;
}

// A calibration key outside calibration mode: error 41.
bool Pr5510Model::require_cal_mode() {
  if (!calibrating_) last_error_ = wg::device_error::kNotInCalMode;
  return calibrating_;
}

bool Pr5510Model::panel_calibrate_zero() {
  if (!require_cal_mode()) return false;
  zero_offset_kg_ = filtered_kg_;
  return true;
}

bool Pr5510Model::panel_calibrate_span(double known_kg) {
  if (!require_cal_mode()) return false;
  const double raw = filtered_kg_ - zero_offset_kg_;
  if (known_kg <= 0.0 || raw <= 0.0) return false;  // the panel refuses a zero or negative span
  span_gain_ = known_kg / raw;
  return true;
}

bool Pr5510Model::panel_finish_calibration() {
  if (!require_cal_mode()) return false;
  calibrating_ = false;
  st_.CalChanged = true;
  return true;
}

void Pr5510Model::finish_command(std::uint8_t error) {
  pending_ = Pending::None;
  st_.CmdBusy = false;
  if (error != wg::device_error::kNone) {
    st_.CmdError = true;
    last_error_ = error;
  }
  if (write_in_progress_) {
    st_.WriteActive = true;  // also on failure, so the handshake ends
    write_in_progress_ = false;
  }
}

void Pr5510Model::run_pending() {
  if (pending_ == Pending::None) return;
  if (st_.StandStill) {
    if (pending_ == Pending::Zero) {
      if (std::abs(filtered_kg_) > cfg_.zero_range)
        return finish_command(wg::device_error::kZeroOutsideRange);
      zero_offset_kg_ = filtered_kg_;
      // The displayed weight jumps to zero; restart the standstill window.
      still_ref_ = 0;
      gross_ = 0;
    } else {
      tare_ = gross_;
      st_.TareActive = true;
    }
    return finish_command(wg::device_error::kNone);
  }
  pending_for_ += kCycle;
  if (pending_for_ > cfg_.tare_timeout) finish_command(wg::device_error::kStandstillTimeout);
}

void Pr5510Model::accept_write(std::uint8_t code, std::uint32_t raw) {
  if (code >= 0x70 && code <= 0x75) {
    // Firmware commands (§5.4); Write_Value is ignored.
    if (pending_ != Pending::None) {
      // Refused because another command waits: acknowledge with the error.
      start_command(static_cast<wg::CommandBit>(code - 0x70));
      st_.WriteActive = true;
      return;
    }
    write_in_progress_ = true;  // finish_command() acknowledges
    start_command(static_cast<wg::CommandBit>(code - 0x70));
    return;
  }
  ++commands_accepted_;
  if (wg::is_defined_write_code(code)) {
    reg_[code] = static_cast<std::int32_t>(raw);
    reg_valid_[code] = 1;
    if (code >= 0x18 && code <= 0x1A) {
      limit_[code - 0x18u] = static_cast<std::int32_t>(raw);
      limit_set_[code - 0x18u] = true;
    }
    st_.CmdError = false;
  } else {
    st_.CmdError = true;  // reserved or unused code ([INFERRED])
  }
  st_.WriteActive = true;
}

void Pr5510Model::serve_read(std::uint8_t code) {
  const bool known = wg::is_defined_read_code(code);
  if (!known && cfg_.strict_codes) return;  // no echo: the master times out
  std::uint32_t v = 0;
  switch (code) {
    case 0x04:
      v = wg::pack_format(
          {cfg_.decimals, static_cast<std::uint8_t>(cfg_.unit), cfg_.division, last_error_},
          cfg_.packed_order);
      break;
    case 0x05:
      v = wg::pack_model({cfg_.model, cfg_.version}, cfg_.packed_order);
      break;
    case 0x08:
      v = static_cast<std::uint32_t>(gross_);
      break;
    case 0x09:
      v = static_cast<std::uint32_t>(gross_ - tare_);
      break;
    case 0x0A:
      v = static_cast<std::uint32_t>(tare_);
      break;
    case 0x0C:
      v = static_cast<std::uint32_t>(
          static_cast<std::int32_t>(std::clamp<std::int64_t>(gross100_, INT32_MIN, INT32_MAX)));
      break;
    case 0x0E:
      v = static_cast<std::uint32_t>(fsd_digits());
      st_.CalChanged = false;  // §3.4: reading the full scale once resets it
      break;
    default:
      if (known) v = static_cast<std::uint32_t>(reg_[code]);
      break;
  }
  io::store<std::uint32_t>(rd_.data() + wg::r::kValue, v, wg::byte_order(cfg_.bus));
  rd_[wg::r::kReadValueSelected] = code;
}

}  // namespace plc::sim

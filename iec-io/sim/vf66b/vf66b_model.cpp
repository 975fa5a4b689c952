#include "vf66b/vf66b_model.hpp"

#include <algorithm>
#include <cmath>

#include "plc/fb/acdrive/protect_codes.hpp"
#include "plc/fb/acdrive/speed_scale.hpp"

namespace plc::sim {

using acdrive::DriveState;

RunEvent run_event(bool prev_run1, bool prev_run2, bool run1, bool run2) {
  // Table 3.4.3, read by the present levels: the row "0 | 0->1" is Run2
  // whether Run1 was 0 before or has just fallen (the row "1->0 | 1").
  if (!run1 && !run2) return RunEvent::Stop;
  if (run1 && run2) return RunEvent::None;  // "0->1 0->1" and "1 1": no action
  if (run1) return (!prev_run1 || prev_run2) ? RunEvent::Run1 : RunEvent::None;
  return (!prev_run2 || prev_run1) ? RunEvent::Run2 : RunEvent::None;
}

Vf66bModel::Vf66bModel(const io::ModelParams& p) : Vf66bModel(vf66b_config_from(p)) {}

Vf66bModel::Vf66bModel(const Vf66bConfig& c) : settings_(c) { power_up(); }

std::size_t Vf66bModel::input_size() const { return acdrive::input_size(in_inst_); }
std::size_t Vf66bModel::output_size() const { return acdrive::output_size(out_inst_); }

void Vf66bModel::power_cycle() { power_up(); }

void Vf66bModel::power_up() {
  act_ = settings_;
  out_inst_ = acdrive::output_instance(act_.j09);
  in_inst_ = acdrive::input_instance(act_.j10);
  speed_scale_ = act_.j11;
  monitors_ = acdrive::monitor_selection(act_.j12);
  // §4.1 of the manual (spec §9.2): at power-up the card sets NetRef
  // (0x2A attr 4) to network iff b-10 = 3, else to local, and ignores the
  // master's speed reference unless b-10 = 3. [reading] §13.4 item 14: the
  // run command source likewise, NetCtrl (0x29 attr 5) = 1 iff b-11 = 3.
  // Both are requests the master may change (Set, bits 5/6 of 21);
  // CtrlFromNet/RefFromNet grant them only with b-11/b-10 = 3.
  ref_permitted_ = act_.b10 == 3;
  ctrl_permitted_ = act_.b11 == 3;
  net_ref_ = ref_permitted_;
  net_ctrl_ = ctrl_permitted_;
  state_ = DriveState::Startup;
  startup_left_s_ = std::chrono::duration<double>(act_.startup_time).count();
  st_f_ = act_.st_f;
  main_power_ = act_.main_power;
  run1_ = run2_ = fault_rst_ = false;
  prev_run1_ = prev_run2_ = false;
  just_reset_ = false;
  speed_ref_ = 0;
  ext_ref_rpm_ = 0;
  motor_type_ = act_.motor_type;
  rated_current_ = act_.rated_current;
  rated_voltage_ = act_.rated_voltage;
  running1_ = running2_ = faulted_ = false;
  reset_pending_ = false;
  faults_ = pending_ = 0;
  // A cause that persists (e.g. an external fault wired on) trips again.
  pending_ = persistent_;
  speed_ = 0;
  torque_pct_ = 0;
}

bool Vf66bModel::ctrl_from_net() const { return ctrl_permitted_ && net_ctrl_; }
bool Vf66bModel::ref_from_net() const { return ref_permitted_ && net_ref_; }

bool Vf66bModel::trip(std::uint8_t code, bool cause_persists) {
  if (!acdrive::is_defined_protect_code(code)) return false;
  pending_ |= acdrive::fault_bit(code);
  if (cause_persists) persistent_ |= acdrive::fault_bit(code);
  return true;
}

void Vf66bModel::io_connection_lost() {
  // [reading] §12: trip only while the drive is under network control; the
  // loss action is not selectable (0x29 attr 16 unsupported), so it is a
  // simulator switch (comm_loss_trip).
  if (act_.comm_loss_trip && (ctrl_from_net() || ref_from_net()))
    trip(static_cast<std::uint8_t>(acdrive::ProtectCode::CommunicationTimeout));
}

// ------------------------------------------------------------------ cyclic
// [reading] Run1/Run2/FaultRst/NetCtrl/NetRef/SpeedRef hold the last value
// written, by an explicit Set or by a consumed output message; see the
// header. consume() is the output message's write.
void Vf66bModel::consume(std::span<const std::uint8_t> from_plc) {
  if (from_plc.size() != output_size()) {
    // §13.1.2: I/O only when the length matches; the frame is ignored.
    ++bad_frames_;
    return;
  }
  bool rst = false;
  bool new_run1 = run1_, new_run2 = run2_;
  if (out_inst_ == 20) {
    acdrive::Output20 o;
    acdrive::decode(from_plc, o);
    new_run1 = o.run_fwd;  // Run2 is not in 20: it keeps its attribute value
    rst = o.fault_reset;
    speed_ref_ = o.speed_ref;
  } else if (out_inst_ == 21) {
    acdrive::Output21 o;
    acdrive::decode(from_plc, o);
    new_run1 = o.run_fwd;
    new_run2 = o.run_rev;
    rst = o.fault_reset;
    net_ctrl_ = o.net_ctrl;
    net_ref_ = o.net_ref;
    speed_ref_ = o.speed_ref;
  } else {
    acdrive::ExtOutput o;
    o.instance = out_inst_;
    acdrive::decode(from_plc, o);
    // §13.3: with PLC-L on, words 1-2 are only PLC relays.
    if (!act_.i00) {
      // [reading] Start/Rev are the drive's run command, which Run1/Run2
      // (0x29 attrs 3/4) also write: Start with Rev off = Run1, with Rev on
      // = Run2.
      new_run1 = o.bits.start && !o.bits.rev;
      new_run2 = o.bits.start && o.bits.rev;
      rst = o.bits.fault_reset2;
      // External faults 1-4 (with or without the 86A relay) are codes 29-32,
      // present while their bit is on.
      const std::array<bool, 4> ext = {
          o.bits.ex_fail1 || o.bits.ex_fail1_no86a, o.bits.ex_fail2 || o.bits.ex_fail2_no86a,
          o.bits.ex_fail3 || o.bits.ex_fail3_no86a, o.bits.ex_fail4 || o.bits.ex_fail4_no86a};
      for (unsigned i = 0; i < 4; ++i) {
        const std::uint32_t b = acdrive::fault_bit(29 + i);
        if (ext[i]) {
          pending_ |= b;
          persistent_ |= b;
        } else {
          persistent_ &= ~b;
        }
      }
    }
    // Speed Reference2: 20000 = top speed (§7.5); [reading] signed INT.
    ext_ref_rpm_ = o.speed_ref2 * act_.top_speed_rpm / 20000.0;
  }
  if (rst && !fault_rst_) reset_pending_ = true;
  fault_rst_ = rst;
  run1_ = new_run1;
  run2_ = new_run2;
}

void Vf66bModel::fault_reset_edge() {
  reset_pending_ = false;
  if (state_ != DriveState::Faulted) return;  // "0 = no action" elsewhere
  if (persistent_ & faults_) return;          // the cause is still there
  faults_ = 0;
  faulted_ = false;
  state_ = DriveState::NotReady;
  just_reset_ = true;
}

double Vf66bModel::reference_rpm() const {
  if (state_ != DriveState::Enabled) return 0;
  double ref = 0;
  if (!ref_from_net()) {
    ref = act_.local_speed_rpm;
  } else if (acdrive::is_extended_output(out_inst_)) {
    ref = ext_ref_rpm_;
  } else {
    ref = acdrive::bus_to_rpm(speed_ref_, speed_scale_);
  }
  // [reading] §13.3: the direction comes from Run1/Run2 (Rev in extended
  // mode); the reference's magnitude is used, clamped to top speed.
  ref = std::min(std::fabs(ref), act_.top_speed_rpm);
  return running2_ ? -ref : ref;
}

bool Vf66bModel::at_reference() const {
  return state_ == DriveState::Enabled && std::fabs(speed_ - reference_rpm()) < 1e-6;
}

bool Vf66bModel::ready_attr() const {
  return state_ == DriveState::Ready || state_ == DriveState::Enabled ||
         state_ == DriveState::Stopping;
}

void Vf66bModel::update_state(double dt_s) {
  // Faults detected since the last step (trip(), io_connection_lost(),
  // external fault bits).
  if (pending_) {
    faults_ |= pending_;
    pending_ = 0;
    faulted_ = true;
    switch (state_) {
      case DriveState::Enabled:
      case DriveState::Stopping:
        state_ = DriveState::FaultStop;
        break;
      case DriveState::FaultStop:
      case DriveState::Faulted:
        break;
      default:
        state_ = DriveState::Faulted;
        break;
    }
  }
  just_reset_ = false;
  if (reset_pending_) fault_reset_edge();

  // Run/Stop events (§5.1) from the levels of the previous step and now.
  // They act only under network control with ST-F on; otherwise the run
  // command is absent (local run inputs are not modelled), which is a Stop.
  RunEvent ev = RunEvent::Stop;
  if (ctrl_from_net() && st_f_) {
    if (acdrive::is_extended_output(out_inst_)) {
      // [reading] extended mode: the run command is a level (terminal
      // style), Start = Run1 or Run2 by Rev; both on (only by explicit Sets)
      // is no action, as in Table 3.4.3.
      if (act_.i00 || (!run1_ && !run2_))
        ev = RunEvent::Stop;
      else if (run1_ != run2_)
        ev = run1_ ? RunEvent::Run1 : RunEvent::Run2;
      else
        ev = RunEvent::None;
    } else {
      ev = run_event(prev_run1_, prev_run2_, run1_, run2_);
      // §13.4 item 21, optional: after a reset the held run level restarts.
      if (ev == RunEvent::None && act_.restart_after_reset && just_reset_ && run1_ != run2_)
        ev = run1_ ? RunEvent::Run1 : RunEvent::Run2;
    }
  }
  prev_run1_ = run1_;
  prev_run2_ = run2_;

  if (state_ == DriveState::Startup) {
    startup_left_s_ -= dt_s;
    if (startup_left_s_ <= 0) state_ = DriveState::NotReady;
    return;
  }
  // Main power (§5.2: Not_Ready <-> Ready; Enabled/Stopping -> Not_Ready).
  if (!main_power_) {
    if (state_ == DriveState::Ready || state_ == DriveState::Enabled ||
        state_ == DriveState::Stopping) {
      state_ = DriveState::NotReady;
      running1_ = running2_ = false;
    }
    if (state_ == DriveState::NotReady) return;  // Fault_Stop still completes
  } else if (state_ == DriveState::NotReady) {
    state_ = DriveState::Ready;
  }

  switch (state_) {
    case DriveState::Ready:
    case DriveState::Stopping:
      if (ev == RunEvent::Run1 || ev == RunEvent::Run2) {
        state_ = DriveState::Enabled;
        running1_ = ev == RunEvent::Run1;
        running2_ = ev == RunEvent::Run2;
      } else if (state_ == DriveState::Stopping && speed_ == 0) {
        state_ = DriveState::Ready;
        running1_ = running2_ = false;
      }
      break;
    case DriveState::Enabled:
      if (ev == RunEvent::Stop) {
        state_ = DriveState::Stopping;
      } else if (ev == RunEvent::Run1 || ev == RunEvent::Run2) {
        running1_ = ev == RunEvent::Run1;
        running2_ = ev == RunEvent::Run2;
      }
      break;
    case DriveState::FaultStop:
      if (speed_ == 0) {
        state_ = DriveState::Faulted;
        running1_ = running2_ = false;
      }
      break;
    default:
      break;
  }
}

void Vf66bModel::update_ramp(double dt_s) {
  const double top = act_.top_speed_rpm;
  double target = reference_rpm();
  double rate = 0;  // r/min per second
  if (state_ == DriveState::Enabled || state_ == DriveState::Stopping) {
    const bool accelerating = std::fabs(target) > std::fabs(speed_) && target * speed_ >= 0;
    const double t = accelerating ? act_.accel_time_s : act_.decel_time_s;
    rate = t > 0 ? top / t : INFINITY;
  } else {
    // gate off (trip, main power off): free run
    target = 0;
    rate = act_.coast_time_s > 0 ? top / act_.coast_time_s : INFINITY;
  }
  const double step = rate * dt_s;
  const double before = speed_;
  if (std::fabs(target - speed_) <= step)
    speed_ = target;
  else
    speed_ += target > speed_ ? step : -step;
  // Torque command: 100 % per top speed per accel time while ramping
  // [model]: the ramp's share only, no load.
  const bool gate = state_ == DriveState::Enabled || state_ == DriveState::Stopping;
  torque_pct_ = gate && dt_s > 0
                    ? (speed_ - before) / dt_s / (top / std::max(act_.accel_time_s, 1e-3)) * 100.0
                    : 0;
}

void Vf66bModel::step(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
                      std::span<std::uint8_t> to_plc) {
  step_io(now, dt, from_plc, true, to_plc);  // the sim plugin: an output message every cycle
}

void Vf66bModel::step_io(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
                         bool new_message, std::span<std::uint8_t> to_plc) {
  now_ = now;
  const double dt_s = std::chrono::duration<double>(dt).count();
  if (act_.fault_code && !injected_ && now >= act_.fault_at) {
    injected_ = true;
    trip(act_.fault_code, act_.fault_persists);
  }
  if (new_message) consume(from_plc);
  update_state(dt_s);
  update_ramp(dt_s);
  // A stop completes in the step that reaches zero speed.
  if ((state_ == DriveState::Stopping || state_ == DriveState::FaultStop) && speed_ == 0)
    update_state(0);
  produce(to_plc);
}

// ------------------------------------------------------------------ produce
std::int16_t Vf66bModel::bus_of(double rpm) const {
  // Saturates at the INT range (§13.3: the scale limits the speed).
  const double v = std::nearbyint(std::ldexp(rpm, speed_scale_));
  return static_cast<std::int16_t>(std::clamp(v, -32768.0, 32767.0));
}

std::int16_t Vf66bModel::speed_actual_bus() const { return bus_of(speed_); }

namespace {
std::uint16_t sat_u16(double v) {
  return static_cast<std::uint16_t>(std::clamp(std::nearbyint(v), 0.0, 65535.0));
}
std::int16_t sat_i16(double v) {
  return static_cast<std::int16_t>(std::clamp(std::nearbyint(v), -32768.0, 32767.0));
}
}  // namespace

std::uint16_t Vf66bModel::monitor_value(unsigned number) const {
  // Table 6.5 items; [reading] §13.4 item 7: ARC out 20000 = top here too.
  const double top = act_.top_speed_rpm;
  const bool gate = state_ == DriveState::Enabled || state_ == DriveState::Stopping;
  const double freq_ratio = std::fabs(speed_) / top;  // output frequency / top
  const bool v200 = act_.voltage_class == 200;
  switch (number) {
    case 1:
      return static_cast<std::uint16_t>(sat_i16(speed_ / top * 20000.0));
    case 2:
      return static_cast<std::uint16_t>(sat_i16(speed_ / top * 20000.0));
    case 3: {
      // [model] magnetising current 30 % plus the torque share, while the
      // gate is on.
      const double pct = gate ? std::sqrt(30.0 * 30.0 + torque_pct_ * torque_pct_) : 0.0;
      return sat_u16(pct * 100.0);
    }
    case 4:
      return static_cast<std::uint16_t>(sat_i16(torque_pct_ * 50.0));
    case 5:
      return sat_u16((v200 ? 10.0 : 5.0) * (v200 ? 282.0 : 565.0));  // DC link at nominal mains
    case 6:
      return sat_u16(gate ? (v200 ? 20.0 : 10.0) * act_.rated_voltage * std::min(freq_ratio, 1.0)
                          : 0.0);
    case 7:
      return sat_u16(freq_ratio * 20000.0);
    case 8:
      return 0;  // OL pre-counter: no overload model
    case 9:
      return sat_u16(25.0 * 10);  // 25 degC motor
    case 10:
      return gate ? 1024 : 0;
    default:
      return 0;
  }
}

acdrive::ExtStatusBits Vf66bModel::status_bits() const {
  acdrive::ExtStatusBits s;
  const bool gate = state_ == DriveState::Enabled || state_ == DriveState::Stopping;
  s.run_or_jog_input = run1_ != run2_;
  s.inverter_running = gate;
  s.reverse_command = running2_;
  s.power_failure = !main_power_;
  s.gate_active = gate;
  s.ext_db_or_comm_error = (faults_ & acdrive::fault_bit(18)) != 0;
  return s;
}

void Vf66bModel::produce(std::span<std::uint8_t> to_plc) const {
  if (to_plc.size() != input_size()) return;
  if (in_inst_ == 70) {
    acdrive::Input70 i;
    i.faulted = faulted_;
    i.running1 = running1_;
    i.speed_actual = speed_actual_bus();
    acdrive::encode(i, to_plc);
  } else if (in_inst_ == 71) {
    acdrive::Input71 i;
    i.faulted = faulted_;
    i.warning = false;  // no warning is modelled (0x29 attr 11, §13.4 item 2)
    i.running1 = running1_;
    i.running2 = running2_;
    i.ready = ready_attr();
    i.ctrl_from_net = ctrl_from_net();
    i.ref_from_net = ref_from_net();
    i.at_reference = at_reference();
    i.state = state_;
    i.speed_actual = speed_actual_bus();
    acdrive::encode(i, to_plc);
  } else if (in_inst_ == 140) {
    acdrive::Input140 i;
    i.status = status_bits();
    i.protect_code = acdrive::lowest_protect_code(faults_);
    for (std::size_t k = 0; k < 3; ++k) i.monitor[k] = monitor_value(monitors_[k]);
    acdrive::encode(i, to_plc, act_.monitor_order);
  } else {
    acdrive::ExtInput i;
    i.instance = in_inst_;
    i.status = status_bits();
    i.faults = faults_;
    i.detect.setting_reached = at_reference();
    i.detect.reverse_rotation = speed_ < 0;
    i.speed_actual2 = static_cast<std::int16_t>(monitor_value(1));
    i.arc_out = static_cast<std::int16_t>(monitor_value(2));
    i.motor_current = monitor_value(3);
    i.torque_command = static_cast<std::int16_t>(monitor_value(4));
    i.dc_voltage = monitor_value(5);
    i.output_voltage = monitor_value(6);
    i.output_frequency = monitor_value(7);
    i.ol_precounter = monitor_value(8);
    i.motor_temperature = static_cast<std::int16_t>(monitor_value(9));
    i.motor_flux = monitor_value(10);
    acdrive::encode(i, to_plc);
  }
}

}  // namespace plc::sim

#include "plc/fb/acdrive/ac_drive.hpp"

#include <cmath>

#include "plc/fb/acdrive/error_ids.hpp"
#include "plc/fb/acdrive/protect_codes.hpp"
#include "plc/fb/acdrive/speed_scale.hpp"

namespace plc::acdrive {

namespace {
constexpr const char* kProfileFaultText = "Drive fault (no protect code in assembly 70/71)";
}

bool AcDrive::config_ok() const {
  const std::size_t out = output_size(OutputInstance);
  const std::size_t in = input_size(InputInstance);
  return out != 0 && in != 0 && Port.out().size() == out && Port.in().size() == in &&
         std::isfinite(TopSpeed) && TopSpeed > 0 && J12 <= 119;
}

void AcDrive::read_inputs() {
  const auto in = Port.in();
  Faulted = Warning = Running = RunningFwd = RunningRev = Ready = AtReference = false;
  CtrlFromNet = RefFromNet = false;
  State = DriveState::VendorSpecific;
  FaultBits = 0;
  ProtectCode = 0;
  Monitor = {};
  if (InputInstance == 70) {
    Input70 i;
    decode(in, i);
    Faulted = i.faulted;
    Running = RunningFwd = i.running1;
    ActualSpeed = bus_to_rpm(i.speed_actual, SpeedScale);
  } else if (InputInstance == 71) {
    Input71 i;
    decode(in, i);
    Faulted = i.faulted;
    Warning = i.warning;
    RunningFwd = i.running1;
    RunningRev = i.running2;
    Running = i.running1 || i.running2;
    Ready = i.ready;
    CtrlFromNet = i.ctrl_from_net;
    RefFromNet = i.ref_from_net;
    AtReference = i.at_reference;
    State = i.state;
    ActualSpeed = bus_to_rpm(i.speed_actual, SpeedScale);
  } else if (InputInstance == 140) {
    Input140 i;
    decode(in, i,
           MonitorManualOrder ? MonitorByteOrder::ManualLiteral : MonitorByteOrder::LittleEndian);
    ProtectCode = i.protect_code;
    Faulted = ProtectCode != 0;
    Running = i.status.inverter_running;
    RunningRev = Running && i.status.reverse_command;
    RunningFwd = Running && !i.status.reverse_command;
    for (std::size_t k = 0; k < 3; ++k) Monitor[k] = i.monitor[k];
    // J-12 combinations are ascending, so Motor speed (item 1) can only be
    // Monitor 1; without it the instance carries no speed.
    ActualSpeed = monitor_selection(J12)[0] == 1
                      ? static_cast<std::int16_t>(i.monitor[0]) * TopSpeed / 20000.0
                      : 0.0;
  } else {
    ExtInput i;
    decode(in, i);
    FaultBits = i.faults;
    ProtectCode = lowest_protect_code(i.faults);
    Faulted = i.faults != 0;
    Running = i.status.inverter_running;
    RunningRev = Running && i.status.reverse_command;
    RunningFwd = Running && !i.status.reverse_command;
    AtReference = i.detect.setting_reached;
    ActualSpeed = i.speed_actual2 * TopSpeed / 20000.0;
  }
  // The text changes only with the code: no string copy in a steady scan.
  const std::int16_t text = ProtectCode != 0 ? ProtectCode : (Faulted ? -1 : 0);
  if (text != text_code_) {
    text_code_ = text;
    FaultText = text > 0 ? protect_code_text(ProtectCode) : (text < 0 ? kProfileFaultText : "");
  }
}

void AcDrive::write_outputs(bool run_fwd, bool run_rev, bool reset, std::int16_t ref_bus,
                            std::int16_t ref2) {
  const auto out = Port.out();
  if (OutputInstance == 20) {
    encode(Output20{run_fwd, reset, ref_bus}, out);
  } else if (OutputInstance == 21) {
    encode(Output21{run_fwd, run_rev, reset, NetCtrl, NetRef, ref_bus}, out);
  } else {
    ExtOutput o;
    o.instance = OutputInstance;
    o.bits.start = run_fwd || run_rev;
    o.bits.rev = run_rev;
    o.bits.fault_reset2 = reset;
    o.speed_ref2 = ref2;
    encode(o, out);
  }
}

void AcDrive::write_safe() {
  if (output_size(OutputInstance) == Port.out().size() && !Port.out().empty())
    write_outputs(false, false, false, 0, 0);
}

void AcDrive::operator()(const ScanContext& ctx) {
  const bool reset_edge = FaultReset && !prev_reset_;
  prev_reset_ = FaultReset;
  ResetActive = false;
  auto lost = [&](std::uint16_t e) {
    Valid = false;
    Error = true;
    ErrorID = e;
    Faulted = Warning = Running = RunningFwd = RunningRev = Ready = AtReference = false;
    CtrlFromNet = RefFromNet = false;
    State = DriveState::VendorSpecific;
    ActualSpeed = 0;
    RestartInhibit = true;
    reset_phase_ = ResetPhase::Idle;
    write_safe();
  };
  if (!Port.bound() || !Port.online()) return lost(error_id::kOffline);
  if (!config_ok()) return lost(error_id::kConfig);

  read_inputs();
  if (!Enable) {
    Valid = false;
    Error = false;
    ErrorID = error_id::kNone;
    reset_phase_ = ResetPhase::Idle;
    write_safe();
    return;
  }
  Valid = true;
  if (Faulted) RestartInhibit = true;

  // Fault reset (§13.2.4): run bits 0 first, then the 0->1 edge, held for
  // ResetPulse, then dropped.
  if (reset_edge && reset_phase_ == ResetPhase::Idle) {
    reset_phase_ = ResetPhase::ClearRun;
    RestartInhibit = true;
  }
  bool reset = false;
  if (reset_phase_ == ResetPhase::ClearRun) {
    reset_phase_ = ResetPhase::Pulse;
    reset_start_ = ctx.now;
  } else if (reset_phase_ == ResetPhase::Pulse) {
    reset = ctx.now - reset_start_ <= ResetPulse;
    if (!reset) reset_phase_ = ResetPhase::Idle;
  }
  ResetActive = reset;

  if (!Faulted && reset_phase_ == ResetPhase::Idle && !RunFwd && !RunRev) RestartInhibit = false;
  // Run bits only while the drive can take them: a run level raised while
  // it starts up or is not ready would be no event of Table 3.4.3 once it
  // is ready (71 shows Ready; 70 and the extended inputs only Faulted).
  const bool accepts = InputInstance == 71 ? Ready : !Faulted;
  const bool may_run = accepts && !RestartInhibit && reset_phase_ == ResetPhase::Idle;
  const bool run_fwd = may_run && RunFwd && !RunRev;
  const bool run_rev = may_run && RunRev && !RunFwd;

  // Speed reference: refused (last valid value kept) when it does not fit.
  bool ref_ok = true;
  const double rpm = std::fabs(SpeedRef);
  if (is_extended_output(OutputInstance)) {
    const double counts = std::nearbyint(rpm / TopSpeed * 20000.0);
    ref_ok = std::isfinite(counts) && counts <= 32767.0;
    if (ref_ok) last_ref2_ = static_cast<std::int16_t>(counts);
  } else {
    const auto bus = rpm_to_bus(rpm, SpeedScale);
    ref_ok = bus.has_value();
    if (ref_ok) last_ref_ = *bus;
  }
  write_outputs(run_fwd, run_rev, reset, last_ref_, last_ref2_);

  if (Faulted)
    ErrorID = error_id::drive_fault(ProtectCode);
  else if (!ref_ok)
    ErrorID = error_id::kSpeedRange;
  else
    ErrorID = error_id::kNone;
  Error = ErrorID != error_id::kNone;
}

}  // namespace plc::acdrive

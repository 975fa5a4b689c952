#include "plc/fb/drive/sina_pos.hpp"

#include "plc/fb/drive/scaling.hpp"

namespace plc::drive {

void SinaPos::operator()(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  const bool exec_edge = ExecuteMode && !prev_exec_;
  const bool exec_fall = !ExecuteMode && prev_exec_;
  const bool ack_edge = AckError && !prev_ack_;
  prev_exec_ = ExecuteMode;
  prev_ack_ = AckError;

  // Power: EnableAxis with the OFF2/OFF3 bits of ConfigEPos.
  const bool no_off2 = (ConfigEPos & 0x1U) != 0, no_off3 = (ConfigEPos & 0x2U) != 0;
  axis.PowerRequest = EnableAxis && no_off2 && no_off3;
  axis.PowerStopMode = !no_off2   ? StopMode::Off2Coast
                       : !no_off3 ? StopMode::Off3Quick
                                  : StopMode::Off1Ramp;
  axis.RequireEnableEdgeAfterReset = RequireEnableEdgeAfterReset;
  // Fault acknowledge: every rising edge of AckError is one reset request
  // with its own STW1.7 edge (DriveAxis::start_reset); AckError held TRUE
  // acknowledges no later fault. Once the drive's fault is gone the error is
  // cleared and EnableAxis, if still TRUE, powers the axis again.
  if (ack_edge) {
    cmd_status_ = cmd_diag_ = 0;
    axis.start_reset(kAckErrorTimeout);
  }
  // Setpoint ranges (Table 3.1.1; SINA_POS: OverV 0..199 %, OverAcc/OverDec
  // 1..100 %): a value outside is refused with Status 16#8203, never
  // clamped. OverV is live: an invalid one leaves the last valid OVERRIDE.
  const auto override_word =
      OverV >= 0 && OverV <= 199 ? to_override(OverV) : std::optional<std::uint16_t>{};
  if (override_word) axis.OVERRIDE = *override_word;
  const auto acc_word =
      OverAcc >= 1 && OverAcc <= 100 ? to_mdi_acc(OverAcc) : std::optional<std::int16_t>{};
  const auto dec_word =
      OverDec >= 1 && OverDec <= 100 ? to_mdi_acc(OverDec) : std::optional<std::int16_t>{};
  const INT acc = acc_word.value_or(0), dec = dec_word.value_or(0);
  const bool dynamics_ok = acc_word && dec_word;

  auto refuse = [&](std::uint16_t status, std::uint16_t diag) {
    cmd_status_ = status;
    cmd_diag_ = diag;
  };
  auto motion_allowed = [&]() -> std::uint16_t {
    if (!axis.positioning()) return kErrTelegram;
    if (const std::uint16_t e = axis.axis_error()) return e;
    if (axis.State == AxisState::Disabled) return kErrDisabled;
    if (axis.State == AxisState::ErrorStop) return kErrErrorStop;
    return 0;
  };

  if (exec_edge) {
    cmd_status_ = cmd_diag_ = 0;
    ActMode = ModePos;
    switch (ModePos) {
      case 1:
      case 2: {
        if (const auto r = motion_allowed())
          refuse(kStatusTaskError, r);
        else if (Velocity <= 0)
          refuse(kStatusBadSetpoint, kErrVelocity);
        else if (!dynamics_ok)
          refuse(kStatusBadSetpoint, kErrAccel);
        else if (axis.State == AxisState::Homing)
          refuse(kStatusTaskError, kErrHoming);
        else
          id_ = axis.start_task(ModePos == 1 ? TaskKind::Relative : TaskKind::Absolute, Position,
                                Velocity, acc, dec);
        break;
      }
      case 3: {
        if (const auto r = motion_allowed())
          refuse(kStatusTaskError, r);
        else if (Velocity <= 0)
          refuse(kStatusBadSetpoint, kErrVelocity);
        else if (!dynamics_ok)
          refuse(kStatusBadSetpoint, kErrAccel);
        else if (Positive == Negative)
          refuse(kStatusBadSetpoint, kErrDirection);
        else {
          id_ = axis.start_task(TaskKind::Velocity, Positive ? 1 : -1, Velocity, acc, dec);
          sent_velocity_ = Velocity;
          sent_acc_ = acc;
          sent_dec_ = dec;
          sent_positive_ = Positive;
        }
        break;
      }
      case 4: {
        if (const auto r = motion_allowed())
          refuse(kStatusTaskError, r);
        else if (axis.State != AxisState::Standstill)
          refuse(kStatusTaskError, kErrNotStandstill);
        else
          id_ = axis.start_homing(HomingTimeout);
        break;
      }
      case 5: {
        if (const auto r = motion_allowed())
          refuse(kStatusTaskError, r);
        else if (axis.Telegram != 111)
          refuse(kStatusBadMode, kErrTelegram);
        else if (axis.State != AxisState::Standstill || !axis.standstill())
          refuse(kStatusTaskError, kErrNotStandstill);
        else {
          setref_ = true;
          axis.SetReferenceRequest = true;
        }
        break;
      }
      case 7:
        break;  // jog works on the Jog1/Jog2 levels
      default:
        refuse(kStatusBadMode, kErrMode);
        break;
    }
  }
  // Mode 3: follow changed setpoints while ExecuteMode stays TRUE; halt when
  // it falls. A change to an invalid setpoint is refused (the task runs on
  // with the last valid one) and shown as 16#8203 while it stays invalid.
  const bool following =
      ModePos == 3 && ExecuteMode && !exec_edge && axis.status(id_) == CmdStatus::Busy;
  std::uint16_t setpoint_diag = override_word ? 0 : kErrOverride;
  if (following && !setpoint_diag) {
    setpoint_diag = Velocity <= 0          ? kErrVelocity
                    : !dynamics_ok         ? kErrAccel
                    : Positive == Negative ? kErrDirection
                                           : 0;
  }
  if (following && !setpoint_diag &&
      (Velocity != sent_velocity_ || acc != sent_acc_ || dec != sent_dec_ ||
       Positive != sent_positive_)) {
    id_ = axis.start_task(TaskKind::Velocity, Positive ? 1 : -1, Velocity, acc, dec);
    sent_velocity_ = Velocity;
    sent_acc_ = acc;
    sent_dec_ = dec;
    sent_positive_ = Positive;
  }
  if (exec_fall && ActMode == 3 && axis.status(id_) == CmdStatus::Busy) {
    id_ = axis.start_halt();
    halting_ = true;
  }
  if (exec_edge) halting_ = false;
  // Mode 5: POS_STW2.1 is held for one drive cycle (the drive acts on its
  // rising edge), then dropped; ZSW1.11 then shows the reference set.
  if (setref_ && !exec_edge) {
    setref_ = false;
    axis.SetReferenceRequest = false;
  }
  // Mode 7: jog levels.
  if (ModePos == 7 && axis.positioning()) {
    const bool jog = (Jog1 || Jog2) && axis.State != AxisState::ErrorStop;
    if (jog && !prev_jog_ && axis.State != AxisState::Disabled) {
      axis.JogRequest1 = Jog1;
      axis.JogRequest2 = Jog2;
      id_ = axis.start_jog();
      ActMode = 7;
    }
    if (axis.active_command() == id_) {
      axis.JogRequest1 = Jog1;
      axis.JogRequest2 = Jog2;
    }
    prev_jog_ = jog;
  } else if (prev_jog_) {
    axis.release(id_);
    prev_jog_ = false;
  }
  // Cancel / pause as levels while this block's task runs (modes 1-3).
  if (axis.active_command() == id_ && ActMode >= 1 && ActMode <= 3 && !halting_) {
    axis.RejectTask = !CancelTraversing;
    axis.IntermediateStop = !IntermediateStop;
  }
  if (axis.status(id_) == CmdStatus::Error && cmd_status_ == 0) {
    cmd_status_ = kStatusTaskError;
    cmd_diag_ = axis.cmd_error(id_);
  }

  // Outputs.
  AxisEnabled = axis.CommOk && axis.operation_enabled();
  AxisRef = axis.homed();
  AxisWarn = (axis.ZSW1 & Zsw1Pos::kWarning) != 0;
  Lockout = ((axis.ZSW1 & Zsw1Pos::kSwitchOnInhibited) != 0 || axis.RestartInhibit) && EnableAxis;
  ActPosition = static_cast<DINT>(axis.ActPosition);
  ActVelocity =
      cu_per_s_to_mdi_velocity(axis.ActVelocity < 0 ? -axis.ActVelocity : axis.ActVelocity) *
      (axis.ActVelocity < 0 ? -1 : 1);
  EPosZSW1 = axis.POS_ZSW1;
  EPosZSW2 = axis.POS_ZSW2;
  ActWarn = axis.WARN_CODE;
  ActFault = axis.FAULT_CODE;
  const bool busy = axis.active_command() == id_ && axis.status(id_) == CmdStatus::Busy;
  AxisPosOk = axis.target_reached() && !busy && AxisEnabled;

  std::uint16_t status = busy || setref_ ? kStatusRunning : kStatusIdle;
  std::uint16_t diag = 0;
  if (axis.CommError) {
    status = kStatusComm;
    diag = axis.CommError;
  } else if (axis.drive_fault()) {
    status = kStatusDriveFault;
    diag = axis.Telegram == 111 ? axis.FAULT_CODE : kErrDriveFault;
  } else if (cmd_status_) {
    status = cmd_status_;
    diag = cmd_diag_;
  } else if (setpoint_diag) {
    status = kStatusBadSetpoint;
    diag = setpoint_diag;
  } else if (axis.State == AxisState::ErrorStop) {
    status = kStatusTaskError;
    diag = kErrErrorStop;
  } else if (EnableAxis && axis.RestartInhibit) {  // error cleared, restart still inhibited
    status = kStatusLockout;
    diag = kErrRestartInhibit;
  } else if (Lockout && !axis.PowerRequest) {  // OFF2/OFF3 forced by ConfigEPos
    status = kStatusLockout;
    diag = kErrLockout;
  }
  Status = status;
  DiagID = diag;
  Error = status >= 0x8000;
  AxisError = Error;
  axis.block_done();
}

}  // namespace plc::drive

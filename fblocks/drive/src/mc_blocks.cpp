#include "plc/fb/drive/mc_blocks.hpp"

#include "plc/fb/drive/scaling.hpp"

namespace plc::drive {

// ------------------------------------------------------------ McExecute
bool McExecute::on_call() {
  const bool edge = Execute && !prev_execute_;
  if ((!Execute && !Busy) || edge) {
    // Falling edge (or a finished command already shown for a scan): reset.
    Done = Error = CommandAborted = false;
    ErrorID = 0;
  }
  prev_execute_ = Execute;
  return edge;
}

void McExecute::finish_done() {
  Done = true;
  Busy = Active = false;
}
void McExecute::finish_error(std::uint16_t e) {
  Error = true;
  ErrorID = e;
  Busy = Active = false;
}
void McExecute::finish_aborted() {
  CommandAborted = true;
  Busy = Active = false;
}

bool McExecute::poll(DriveAxis& axis) {
  if (!Busy) return false;
  if (const std::uint16_t e = axis.axis_error()) {
    finish_error(e);
    return true;
  }
  switch (axis.status(id_)) {
    case CmdStatus::Busy:
      Active = true;
      return false;
    case CmdStatus::Done:
      finish_done();
      return true;
    case CmdStatus::Error:
      finish_error(axis.cmd_error(id_));
      return true;
    case CmdStatus::Aborted:
      finish_aborted();
      return true;
  }
  return false;
}

std::uint16_t McExecute::motion_refusal(const DriveAxis& axis) {
  if (!axis.positioning()) return kErrTelegram;
  if (const std::uint16_t e = axis.axis_error()) return e;
  switch (axis.State) {
    case AxisState::Disabled:
      return kErrDisabled;
    case AxisState::ErrorStop:
      return kErrErrorStop;
    case AxisState::Stopping:
      return kErrStopping;
    case AxisState::Homing:
      return kErrHoming;
    default:
      return 0;
  }
}

std::optional<INT> accel_to_mdi(const DriveAxis& axis, LREAL accel, bool deceleration) {
  if (accel == 0) return INT{0x4000};  // 0: the drive's own 100 % ramp
  const double ref = ramp_time_to_accel(rpm_to_cu_per_s(axis.RefSpeedRpm, axis.CuPerRev),
                                        deceleration ? axis.DecTimeMs : axis.AccTimeMs);
  // Negative, NaN, infinite, above 100 % (the E1's limit), or below the
  // smallest step of MDI_ACC (a ramp that would never end): refused.
  if (!(accel > 0) || !(ref > 0)) return std::nullopt;
  const auto v = to_mdi_acc(accel / ref * 100.0);
  if (!v || *v < 1) return std::nullopt;
  return INT{*v};
}

// ------------------------------------------------------------ MC_Reset
void MC_Reset::run(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  if (on_call()) {
    Busy = true;
    axis.start_reset(Timeout);  // a new STW1.7 edge for this request
  } else if (Busy) {
    switch (axis.reset_status()) {
      case DriveAxis::ResetStatus::Done:
        finish_done();
        break;
      case DriveAxis::ResetStatus::Error:
        finish_error(axis.reset_error());
        break;
      default:
        break;
    }
  }
  axis.block_done();
}

// ------------------------------------------------------------ moves
void McExecute::start_positioning(DriveAxis& axis, TaskKind kind, LREAL target, LREAL velocity,
                                  LREAL acceleration, LREAL deceleration) {
  // Table 3.1.1: every setpoint must fit its field; nothing is wrapped or
  // clamped (MDI_TARPOS is Int32: 3e9 CU would go out as -1294967296).
  const std::uint16_t r = motion_refusal(axis);
  const auto pos = to_mdi_tarpos(target);
  const auto v = to_mdi_velocity(velocity);
  const auto acc = accel_to_mdi(axis, acceleration, false);
  const auto dec = accel_to_mdi(axis, deceleration, true);
  if (r)
    finish_error(r);
  else if (!pos)
    finish_error(kErrPosition);
  else if (!v || *v <= 0)
    finish_error(kErrVelocity);
  else if (!acc || !dec)
    finish_error(kErrAccel);
  else {
    id_ = axis.start_task(kind, *pos, *v, *acc, *dec);
    Busy = true;
  }
}

void MC_MoveAbsolute::run(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  if (on_call())
    start_positioning(axis, TaskKind::Absolute, Position, Velocity, Acceleration, Deceleration);
  poll(axis);
  axis.block_done();
}

void MC_MoveRelative::run(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  if (on_call())
    start_positioning(axis, TaskKind::Relative, Distance, Velocity, Acceleration, Deceleration);
  poll(axis);
  axis.block_done();
}

void MC_MoveVelocity::operator()(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  if (on_call()) {
    const std::uint16_t r = motion_refusal(axis);
    const auto v = to_mdi_velocity(Velocity);
    const auto acc = accel_to_mdi(axis, Acceleration, false);
    const auto dec = accel_to_mdi(axis, Deceleration, true);
    InVelocity = false;
    if (r)
      finish_error(r);
    else if (!v || *v <= 0)
      finish_error(kErrVelocity);
    else if (!acc || !dec)
      finish_error(kErrAccel);
    else if (Direction != kMcPositiveDirection && Direction != kMcNegativeDirection)
      finish_error(kErrDirection);
    else {
      id_ = axis.start_task(TaskKind::Velocity, Direction == kMcNegativeDirection ? -1 : 1, *v,
                            *acc, *dec);
      Busy = true;
    }
  }
  poll(axis);
  InVelocity = Busy && axis.in_velocity(id_);
  if (!Execute && !Busy) InVelocity = false;
  axis.block_done();
}

void MC_Home::operator()(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  if (on_call()) {
    std::uint16_t r = motion_refusal(axis);
    if (!r && axis.State != AxisState::Standstill) r = kErrNotStandstill;
    // Position is not sent (the E1 homes to its own parameters), but a value
    // no drive could take is refused rather than dropped without a word.
    if (!r && !to_mdi_tarpos(Position)) r = kErrPosition;
    if (r)
      finish_error(r);
    else {
      id_ = axis.start_homing(Timeout);
      Busy = true;
    }
  }
  poll(axis);
  axis.block_done();
}

void MC_Stop::operator()(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  if (on_call()) {
    std::uint16_t r = axis.positioning() ? axis.axis_error() : kErrTelegram;
    if (!r && axis.State == AxisState::Disabled) r = kErrDisabled;
    if (r)
      finish_error(r);
    else {
      id_ = axis.start_stop();
      Busy = true;
      held_ = true;
    }
  }
  poll(axis);
  // Stopping lasts while Execute is TRUE (PLCopen), then Standstill.
  if (held_ && !Busy && !Execute) {
    axis.end_stop(id_);
    held_ = false;
    axis.update_state();
  }
  axis.block_done();
}

void MC_Halt::operator()(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  if (on_call()) {
    const std::uint16_t r = motion_refusal(axis);
    if (r)
      finish_error(r);
    else {
      id_ = axis.start_halt();
      Busy = true;
    }
  }
  poll(axis);
  axis.block_done();
}

void MC_ReadStatus::operator()(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  Valid = Enable;
  Busy = Enable;
  Error = false;
  ErrorID = 0;
  const AxisState s = axis.State;
  ErrorStop = Enable && s == AxisState::ErrorStop;
  Disabled = Enable && s == AxisState::Disabled;
  Stopping = Enable && s == AxisState::Stopping;
  Homing = Enable && s == AxisState::Homing;
  Standstill = Enable && s == AxisState::Standstill;
  DiscreteMotion = Enable && s == AxisState::DiscreteMotion;
  ContinuousMotion = Enable && s == AxisState::ContinuousMotion;
  SynchronizedMotion = Enable && s == AxisState::SynchronizedMotion;
  axis.block_done();
}

void MC_ReadActualPosition::operator()(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  const std::uint16_t e = Enable ? axis.CommError.value : std::uint16_t{0};
  Error = e != 0;
  ErrorID = e;
  Valid = Enable && !Error;
  Busy = Enable;
  if (Valid) Position = axis.ActPosition;
  axis.block_done();
}

}  // namespace plc::drive

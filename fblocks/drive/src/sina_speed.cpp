#include "plc/fb/drive/sina_speed.hpp"

#include "plc/fb/drive/scaling.hpp"

namespace plc::drive {

void SinaSpeed::operator()(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  const bool no_off2 = (ConfigAxis & 0x1U) != 0, no_off3 = (ConfigAxis & 0x2U) != 0;
  axis.PowerRequest = EnableAxis && no_off2 && no_off3;
  axis.PowerStopMode = !no_off2   ? StopMode::Off2Coast
                       : !no_off3 ? StopMode::Off3Quick
                                  : StopMode::Off1Ramp;
  axis.RequireEnableEdgeAfterReset = RequireEnableEdgeAfterReset;
  // Each AckError edge is one reset request with its own STW1.7 edge (as
  // SinaPos).
  if (AckError && !prev_ack_) axis.start_reset(kAckErrorTimeout);
  prev_ack_ = AckError;
  // Table 3.1.1: NSOLL_B is Int32 (0x40000000 = 100 %): a speed of 200 % of
  // RefSpeed or more, a RefSpeed <= 0 or a non-finite input is refused (the
  // last valid setpoint stays on the wire), never saturated.
  const auto nsoll_b = to_nsoll_b(SpeedSp, RefSpeed);
  if (nsoll_b) axis.NSOLL_B = *nsoll_b;

  AxisEnabled = axis.CommOk && axis.operation_enabled();
  Lockout = ((axis.ZSW1 & Zsw1Speed::kSwitchOnInhibited) != 0 || axis.RestartInhibit) && EnableAxis;
  ActVelocity = static_cast<REAL>(nist_b_to_speed(axis.NIST_B, RefSpeed > 0 ? RefSpeed : 0));
  SpeedReached = AxisEnabled && (axis.ZSW1 & Zsw1Speed::kSpeedReached) != 0;
  InTolerance = AxisEnabled && (axis.ZSW1 & Zsw1Speed::kSpeedErrorInTolerance) != 0;
  std::uint16_t status = AxisEnabled ? kStatusRunning : kStatusIdle, diag = 0;
  if (axis.Telegram != 3) {
    status = kStatusComm;
    diag = kErrTelegram;
  } else if (axis.CommError) {
    status = kStatusComm;
    diag = axis.CommError;
  } else if (axis.drive_fault()) {
    status = kStatusDriveFault;
    diag = kErrDriveFault;
  } else if (!nsoll_b) {
    status = kStatusBadSetpoint;
    diag = kErrSpeedSetpoint;
  } else if (axis.State == AxisState::ErrorStop) {
    status = kStatusTaskError;
    diag = kErrErrorStop;
  } else if (EnableAxis && axis.RestartInhibit) {  // error cleared, restart still inhibited
    status = kStatusLockout;
    diag = kErrRestartInhibit;
  } else if (Lockout && !axis.PowerRequest) {
    status = kStatusLockout;
    diag = kErrLockout;
  }
  Status = status;
  DiagID = diag;
  Error = status >= 0x8000;
  (void)ctx;
  axis.block_done();
}

}  // namespace plc::drive

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
  axis.AckRequest = AckError;
  if (AckError && !prev_ack_) {
  }
  if (AckError && !axis.drive_fault() && axis.State == AxisState::ErrorStop) {
    axis.reset_errors();
    axis.update_state();
  }
  prev_ack_ = AckError;
  axis.NSOLL_B = speed_to_nsoll_b(SpeedSp, RefSpeed);

  AxisEnabled = axis.CommOk && axis.operation_enabled();
  Lockout = (axis.ZSW1 & Zsw1Speed::kSwitchOnInhibited) != 0 && EnableAxis;
  ActVelocity = static_cast<REAL>(nist_b_to_speed(axis.NIST_B, RefSpeed));
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
  } else if (axis.State == AxisState::ErrorStop) {
    status = kStatusTaskError;
    diag = kErrErrorStop;
  } else if (Lockout && !axis.PowerRequest) {
    status = kStatusLockout;
    diag = kErrLockout;
  }
  Status = status;
  DiagID = diag;
  Error = status >= 0x8000;
  (void)ctx;
  axis.commit();
}

}  // namespace plc::drive

#include "plc/fb/drive/diag_codes.hpp"

#include "plc/fb/drive/parameter_channel.hpp"

namespace plc::drive {

const char* diag_text(std::uint16_t c) {
  if ((c & 0xFF00) == kErrParamResponse) return param_error_text(c & 0xFF);
  if ((c & 0xFF00) == kErrParamRecord) return "record write/read refused by the device";
  switch (c) {
    case kErrNone:
      return "";
    case kErrOffline:
      return "device not online";
    case kErrSignOfLife:
      return "drive sign-of-life stalled";
    case kErrTelegram:
      return "telegram does not suit the block";
    case kErrDriveFault:
      return "drive fault";
    case kErrErrorStop:
      return "axis in ErrorStop";
    case kErrRestartInhibit:
      return "restart inhibited after an error: reset, or give Enable again";
    case kErrDisabled:
      return "axis disabled";
    case kErrStopping:
      return "axis stopping";
    case kErrHoming:
      return "axis homing";
    case kErrNotStandstill:
      return "axis not in standstill";
    case kErrVelocity:
      return "velocity not finite or outside the MDI_VELOCITY range";
    case kErrAccel:
      return "acceleration or deceleration out of range";
    case kErrDirection:
      return "invalid direction";
    case kErrMode:
      return "mode not supported";
    case kErrPosition:
      return "position outside the Int32 range of MDI_TARPOS";
    case kErrOverride:
      return "velocity override outside 0..199 %";
    case kErrSpeedSetpoint:
      return "speed setpoint outside the NSOLL_B range";
    case kErrTaskNotAck:
      return "traversing task not acknowledged";
    case kErrHomingTimeout:
      return "homing timeout";
    case kErrEnableTimeout:
      return "enable timeout";
    case kErrLockout:
      return "switch-on inhibited";
    case kErrResetTimeout:
      return "fault persists after acknowledge";
    case kErrTaskCancelled:
      return "traversing task cancelled by the drive";
    case kErrParamRefMismatch:
      return "response reference mismatch";
    case kErrParamIdMismatch:
      return "response ID mismatch";
    case kErrParamMalformed:
      return "malformed response";
    case kErrParamTimeout:
      return "parameter access timeout";
    case kErrParamInput:
      return "invalid block input";
    case kErrParamCount:
      return "response value count mismatch";
    case kErrParamValue:
      return "value does not fit the parameter format";
    case kErrAbsEnabled:
      return "refused: axis enabled";
    case kErrAbsDisableTimeout:
      return "axis did not disable";
    case kErrAbsRunningTimeout:
      return "multi-turn clear still running (2) at timeout";
    case kErrAbsNoStartTimeout:
      return "multi-turn clear did not start";
    case kErrAbsResetTimeout:
      return "drive not back after reset";
    case kErrAbsRefused:
      return "multi-turn clear refused: motor enabled (16)";
    case kErrAbsFailed:
      return "multi-turn clear failed (32)";
    default:
      return "";
  }
}

const char* status_text(std::uint16_t s) {
  switch (s) {
    case kStatusIdle:
      return "no job running";
    case kStatusRunning:
      return "job running";
    case kStatusBadMode:
      return "wrong mode";
    case kStatusBadSetpoint:
      return "invalid setpoint";
    case kStatusDriveFault:
      return "drive fault";
    case kStatusLockout:
      return "switch-on inhibited";
    case kStatusComm:
      return "no valid cyclic data";
    case kStatusTaskError:
      return "traversing handshake failed";
    default:
      return "";
  }
}

}  // namespace plc::drive

// Every Status, DiagID and ErrorID value the drive blocks define, in one
// place (also in fblocks/drive/README.md).
//
// ErrorID of the axis, MC_* blocks, SinaPos/SinaSpeed DiagID (WORD):
// | value    | name                    | meaning |
// |----------|-------------------------|-------------------------------------------------------------|
// | 16#0000  | kErrNone                | no error | | 16#8001  | kErrOffline             | device
// not online (not bound, stopped answering, rebooting) | | 16#8002  | kErrSignOfLife          |
// drive sign-of-life (ZSW2.12-15) stalled > tolerance scans   | | 16#8003  | kErrTelegram | the
// axis telegram does not suit the block (e.g. MDI on 3)   | | 16#8004  | kErrDriveFault          |
// drive reports a fault (ZSW1.3); FAULT_CODE in ActFault      | | 16#8005  | kErrErrorStop |
// command refused: axis in ErrorStop (MC_Reset first)         | | 16#8010  | kErrDisabled | command
// refused: axis Disabled (MC_Power not on)            | | 16#8011  | kErrStopping            |
// command refused: axis Stopping (MC_Stop still active)       | | 16#8012  | kErrHoming | command
// refused: axis Homing                                | | 16#8013  | kErrNotStandstill       |
// command refused: needs Standstill (MC_Home, set reference)  | | 16#8020  | kErrVelocity |
// Velocity <= 0 or out of range                               | | 16#8021  | kErrAccel |
// Acceleration/Deceleration < 0                               | | 16#8022  | kErrDirection |
// Direction/Positive/Negative invalid (none or both)          | | 16#8023  | kErrMode |
// ModePos/StopMode not supported                              | | 16#8030  | kErrTaskNotAck |
// traversing task not acknowledged (ZSW1.12) in AckTimeout    | | 16#8031  | kErrHomingTimeout |
// homing not finished in HomingTimeout                        | | 16#8032  | kErrEnableTimeout |
// MC_Power: operation (S4) not reached in EnableTimeout       | | 16#8033  | kErrLockout |
// switch-on inhibited (S1) persists in EnableTimeout          | | 16#8034  | kErrResetTimeout |
// fault still present after acknowledge (cause not gone)      | | 16#8035  | kErrTaskCancelled |
// the drive dropped the task (overtravel, disable) before end |
//
// SinaPos / SinaSpeed Status (WORD), Siemens FB284/FB285-like:
// | 16#7000  | kStatusIdle             | enabled or disabled, no traversing job running | | 16#7002
// | kStatusRunning          | job running (normal operation)                              | |
// 16#8202  | kStatusBadMode          | ModePos not supported (DiagID kErrMode) | | 16#8203  |
// kStatusBadSetpoint      | invalid Velocity/override/direction (DiagID kErrVelocity..) | | 16#8401
// | kStatusDriveFault       | drive fault (DiagID = FAULT_CODE of telegram 111, or 8004)  | |
// 16#8402  | kStatusLockout          | switch-on inhibited persists (DiagID kErrLockout) | |
// 16#8600  | kStatusComm             | no valid cyclic data (DiagID kErrOffline / kErrSignOfLife /
// | |          |                         | kErrTelegram) | | 16#8601  | kStatusTaskError        |
// traversing handshake failed (DiagID kErrTaskNotAck, ...)    |
//
// Parameter access (SinaPara, AbsEncoderInit) ErrorID:
// | 16#81xx  | kErrParamResponse + xx  | negative parameter response, xx = error number of spec
// §6.5 | |          |                         | (Table 4.3.6.1); ErrorText gives its name | |
// 16#8200  | kErrParamRefMismatch    | response reference != request reference | | 16#8201  |
// kErrParamIdMismatch     | response ID does not answer the request ID                  | | 16#8202
// | kErrParamMalformed      | response too short or inconsistent                          | |
// 16#8203  | kErrParamTimeout        | no response within Timeout | | 16#8204  | kErrParamInput |
// invalid block input (Count, Format, record busy)            | | 16#8205  | kErrParamCount |
// response carries a different number of values              | | 16#83xx  | kErrParamRecord + xx |
// record write/read refused, xx = plc::io::RecordError        |
//
// AbsEncoderInit ErrorID (plus the parameter-access codes above):
// | 16#9001  | kErrAbsEnabled          | refused by the block: axis enabled and AllowDisable FALSE
// | | 16#9002  | kErrAbsDisableTimeout   | axis did not disable in Timeout | | 16#9004  |
// kErrAbsRunningTimeout   | 3200h still 2 (running) at Timeout                          | | 16#9005
// | kErrAbsNoStartTimeout   | 3200h never reached 2/4 (read 0 or 1) in Timeout            | |
// 16#9006  | kErrAbsResetTimeout     | drive not back (online) after the 3215h reset in Timeout |
// | 16#9016  | kErrAbsRefused          | drive refused: 3200h = 16 (motor enabled) | | 16#9032  |
// kErrAbsFailed           | drive failed: 3200h = 32                                    |
#pragma once

#include <cstdint>

namespace plc::drive {

// Setpoint range checks (spec Table 3.1.1) and the restart inhibit (PLCopen
// MC Part 1 state diagram, ErrorStop) add:
// | 16#8006 | kErrRestartInhibit | power refused after an error although no error is latched:
// |         |                    | with RequireEnableEdgeAfterReset, give Enable a new rising edge
// |         |                    | (FALSE for a scan, then TRUE); after AbsEncoderInit's own
// |         |                    | drive reset, MC_Reset/AckError (or a new Enable edge)
// | 16#8024 | kErrPosition       | Position/Distance not finite or outside Int32 (MDI_TARPOS)
// | 16#8025 | kErrOverride       | SinaPos OverV outside 0..199 % (OVERRIDE 0..32767)
// | 16#8026 | kErrSpeedSetpoint  | SinaSpeed SpeedSp/RefSpeed: not finite, RefSpeed <= 0, or
// |         |                    | NSOLL_B outside Int32 (|SpeedSp| >= 200 % of RefSpeed)
// | 16#8206 | kErrParamValue     | SinaPara write value does not fit Format (Table 4.3.5.1
// |         |                    | range) or is not finite
// and widen kErrVelocity (not finite, or MDI_VELOCITY outside 1..2^31-1) and
// kErrAccel (not finite, < 0, above 100 % of Pt534/Pt537 or below one step
// of MDI_ACC/MDI_DEC; SinaPos OverAcc/OverDec outside 1..100).
inline constexpr std::uint16_t kErrNone = 0x0000;
inline constexpr std::uint16_t kErrOffline = 0x8001;
inline constexpr std::uint16_t kErrSignOfLife = 0x8002;
inline constexpr std::uint16_t kErrTelegram = 0x8003;
inline constexpr std::uint16_t kErrDriveFault = 0x8004;
inline constexpr std::uint16_t kErrErrorStop = 0x8005;
inline constexpr std::uint16_t kErrRestartInhibit = 0x8006;
inline constexpr std::uint16_t kErrDisabled = 0x8010;
inline constexpr std::uint16_t kErrStopping = 0x8011;
inline constexpr std::uint16_t kErrHoming = 0x8012;
inline constexpr std::uint16_t kErrNotStandstill = 0x8013;
inline constexpr std::uint16_t kErrVelocity = 0x8020;
inline constexpr std::uint16_t kErrAccel = 0x8021;
inline constexpr std::uint16_t kErrDirection = 0x8022;
inline constexpr std::uint16_t kErrMode = 0x8023;
inline constexpr std::uint16_t kErrPosition = 0x8024;
inline constexpr std::uint16_t kErrOverride = 0x8025;
inline constexpr std::uint16_t kErrSpeedSetpoint = 0x8026;
inline constexpr std::uint16_t kErrTaskNotAck = 0x8030;
inline constexpr std::uint16_t kErrHomingTimeout = 0x8031;
inline constexpr std::uint16_t kErrEnableTimeout = 0x8032;
inline constexpr std::uint16_t kErrLockout = 0x8033;
inline constexpr std::uint16_t kErrResetTimeout = 0x8034;
inline constexpr std::uint16_t kErrTaskCancelled = 0x8035;

inline constexpr std::uint16_t kStatusIdle = 0x7000;
inline constexpr std::uint16_t kStatusRunning = 0x7002;
inline constexpr std::uint16_t kStatusBadMode = 0x8202;
inline constexpr std::uint16_t kStatusBadSetpoint = 0x8203;
inline constexpr std::uint16_t kStatusDriveFault = 0x8401;
inline constexpr std::uint16_t kStatusLockout = 0x8402;
inline constexpr std::uint16_t kStatusComm = 0x8600;
inline constexpr std::uint16_t kStatusTaskError = 0x8601;

inline constexpr std::uint16_t kErrParamResponse = 0x8100;
inline constexpr std::uint16_t kErrParamRefMismatch = 0x8200;
inline constexpr std::uint16_t kErrParamIdMismatch = 0x8201;
inline constexpr std::uint16_t kErrParamMalformed = 0x8202;
inline constexpr std::uint16_t kErrParamTimeout = 0x8203;
inline constexpr std::uint16_t kErrParamInput = 0x8204;
inline constexpr std::uint16_t kErrParamCount = 0x8205;
inline constexpr std::uint16_t kErrParamValue = 0x8206;
inline constexpr std::uint16_t kErrParamRecord = 0x8300;

inline constexpr std::uint16_t kErrAbsEnabled = 0x9001;
inline constexpr std::uint16_t kErrAbsDisableTimeout = 0x9002;
inline constexpr std::uint16_t kErrAbsRunningTimeout = 0x9004;
inline constexpr std::uint16_t kErrAbsNoStartTimeout = 0x9005;
inline constexpr std::uint16_t kErrAbsResetTimeout = 0x9006;
inline constexpr std::uint16_t kErrAbsRefused = 0x9016;
inline constexpr std::uint16_t kErrAbsFailed = 0x9032;

// Short English text of an ErrorID/DiagID above ("" if unknown); for 16#81xx
// the §6.5 error name. Status codes share numbers with ErrorIDs (they are
// different outputs), so they have their own status_text().
const char* diag_text(std::uint16_t code);
const char* status_text(std::uint16_t status);

}  // namespace plc::drive

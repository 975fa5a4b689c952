// SinaSpeed: speed axis in the style of Siemens SINA_SPEED (FB285) over
// standard telegram 3 of the HIWIN E1 (SINA_SPEED's own telegram 1 is not
// supported by the E1, spec §9.2). NSOLL_B = SpeedSp / RefSpeed x 0x40000000
// (spec §2, §7.1: 0x40000000 = 100 % of the reference speed Pt317; RefSpeed
// must equal Pt317); ActVelocity from NIST_B. A setpoint that does not fit
// NSOLL_B (|SpeedSp| >= 200 % of RefSpeed, RefSpeed <= 0, NaN, infinity) is
// refused: the last valid NSOLL_B stays on the wire and Status is 16#8203
// with DiagID 16#8026 while the input stays invalid.
// EnableAxis walks S1 -> S4 like MC_Power; ConfigAxis bit 0 = 0 forces OFF2,
// bit 1 = 0 forces OFF3 (default 16#3); EnableAxis FALSE is OFF1.
// Each AckError edge acknowledges the drive's fault (its own STW1.7 edge)
// and clears the axis error; EnableAxis held TRUE then powers the axis
// again, never before the AckError. RequireEnableEdgeAfterReset = TRUE
// keeps power off until EnableAxis is given again (Lockout, Status
// 16#8402, DiagID 16#8006).
// Status/DiagID as SinaPos (diag_codes.hpp): 16#7000 disabled/idle,
// 16#7002 running (S4), 16#8203 bad setpoint (DiagID 16#8026), 16#8401 fault
// (DiagID 16#8004), 16#8402 lockout (DiagID 8033 or 8006), 16#8600 no valid
// cyclic data (DiagID 8001/8002/8003).
#pragma once

#include "plc/fb/drive/drive_axis.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::drive {

struct SinaSpeed {
  BOOL EnableAxis{};
  BOOL AckError{};
  REAL SpeedSp{};        // rpm
  REAL RefSpeed = 3000;  // rpm, = Pt317
  WORD ConfigAxis = 0x3;
  BOOL RequireEnableEdgeAfterReset{};
  BOOL AxisEnabled{};
  BOOL Lockout{};
  REAL ActVelocity{};   // rpm
  BOOL SpeedReached{};  // ZSW1.10
  BOOL InTolerance{};   // ZSW1.8
  BOOL Error{};
  WORD Status = 0x7000;
  WORD DiagID{};

  void operator()(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(EnableAxis, AckError, SpeedSp, RefSpeed, ConfigAxis, RequireEnableEdgeAfterReset,
              AxisEnabled, Lockout, ActVelocity, SpeedReached, InTolerance, Error, Status, DiagID,
              /* internal state */ prev_ack_)
  PLC_INTERNAL(prev_ack_)
  bool prev_ack_ = false;
};

}  // namespace plc::drive

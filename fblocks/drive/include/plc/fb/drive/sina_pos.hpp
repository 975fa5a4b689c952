// SinaPos: MDI positioning in the style of Siemens SINA_POS (FB284) over
// telegram 111 (or 9) of the HIWIN E1, on a DriveAxis.
//
// ModePos (latched on the rising edge of ExecuteMode; 1-3 may be
// re-triggered while moving):
//   1 relative positioning   Position = distance (CU), Velocity (1000 CU/min)
//   2 absolute positioning   Position = target (CU)
//   3 setup / velocity       travel in the Positive or Negative direction at
//                            Velocity while ExecuteMode is TRUE; a change of
//                            Velocity/OverAcc/OverDec/direction re-sends the
//                            task; ExecuteMode FALSE halts (intermediate stop,
//                            then the task is dropped). [INF] The E1 has no
//                            setup submode (spec §7.6): sent as a relative task
//                            to the far end of the 32-bit range.
//   4 active homing          drive-internal homing (STW1.11), spec §7.8
//   5 set reference point    POS_STW2.1 (telegram 111 only), at standstill
//   7 jog                    Jog1/Jog2 levels -> STW1.8/.9 (Pt533 speed, Pt53A)
// Other values give Status 16#8202. OverV (0..199 %) drives OVERRIDE live
// (telegram 111), OverAcc/OverDec (1..100 %) MDI_ACC/MDI_DEC. Values outside
// these ranges are refused, never clamped (Status 16#8203, DiagID 16#8025
// for OverV, 16#8021 for OverAcc/OverDec): an invalid OverV leaves the last
// valid OVERRIDE on the wire, an invalid OverAcc/OverDec refuses the command
// (in mode 3 the change; the task runs on with its last valid setpoints).
// CancelTraversing = FALSE rejects the task (STW1.4 = 0, Pt538 ramp);
// IntermediateStop = FALSE pauses it (STW1.5 = 0), TRUE again resumes.
// ConfigEPos bit 0 = 0 forces OFF2, bit 1 = 0 forces OFF3 (default 16#3).
// AckError: each rising edge acknowledges the drive's fault with its own
// STW1.7 edge (0, then 1 until the fault is gone, then 0; dropped after 1 s
// if the fault persists) and clears the block's and the axis' errors once
// the fault is gone. EnableAxis is level-controlled, as in the TIA SINA_POS:
// held TRUE through the fault and the AckError, it powers the axis again
// (from switching on inhibited: OFF1 first, then ON and enable operation);
// never before the AckError, also not when the drive simply answers again.
// RequireEnableEdgeAfterReset = TRUE keeps power off after the AckError too
// (Lockout, Status 16#8402, DiagID 16#8006) until EnableAxis has been FALSE
// for a scan and is TRUE again.
//
// Outputs: AxisEnabled (ZSW1.2), AxisPosOk (ZSW1.10 with no task running),
// AxisRef (ZSW1.11), AxisWarn (ZSW1.7), AxisError, Lockout (ZSW1.6),
// ActPosition (CU), ActVelocity (1000 CU/min), ActMode, EPosZSW1/2
// (POS_ZSW1/2), ActWarn (WARN_CODE), ActFault (FAULT_CODE), Error, Status,
// DiagID. Status and DiagID values: diag_codes.hpp and README.md:
//   16#7000 idle, 16#7002 job running, 16#8202 bad ModePos (DiagID 8023),
//   16#8203 bad setpoint (DiagID 8020/8021/8022/8025), 16#8401 drive fault
//   (DiagID = FAULT_CODE on telegram 111, 16#8004 on 9), 16#8402 lockout
//   (DiagID 8033, or 8006 while the restart is inhibited),
//   16#8600 no valid cyclic data (DiagID 8001/8002/8003), 16#8601 handshake
//   failed (DiagID 8030/8031/8035, or the refusal 8010-8013).
#pragma once

#include "plc/fb/drive/drive_axis.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::drive {

struct SinaPos {
  // inputs
  INT ModePos{};
  BOOL EnableAxis{};
  BOOL CancelTraversing = true;
  BOOL IntermediateStop = true;
  BOOL Positive{};
  BOOL Negative{};
  BOOL Jog1{};
  BOOL Jog2{};
  BOOL FlyRef{};  // not supported by the E1; ignored
  BOOL AckError{};
  BOOL ExecuteMode{};
  DINT Position{};
  DINT Velocity{};  // 1000 CU/min (MDI_VELOCITY units)
  INT OverV = 100;
  INT OverAcc = 100;
  INT OverDec = 100;
  DWORD ConfigEPos = 0x3;
  TIME HomingTimeout = std::chrono::seconds(60);
  BOOL RequireEnableEdgeAfterReset{};
  // outputs
  BOOL AxisEnabled{};
  BOOL AxisPosOk{};
  BOOL AxisRef{};
  BOOL AxisWarn{};
  BOOL AxisError{};
  BOOL Lockout{};
  DINT ActPosition{};
  DINT ActVelocity{};
  INT ActMode{};
  WORD EPosZSW1{};
  WORD EPosZSW2{};
  WORD ActWarn{};
  WORD ActFault{};
  BOOL Error{};
  WORD Status = 0x7000;
  WORD DiagID{};

  void operator()(const ScanContext& ctx, DriveAxis& axis);

  PLC_REFLECT(ModePos, EnableAxis, CancelTraversing, IntermediateStop, Positive, Negative, Jog1,
              Jog2, FlyRef, AckError, ExecuteMode, Position, Velocity, OverV, OverAcc, OverDec,
              ConfigEPos, HomingTimeout, RequireEnableEdgeAfterReset, AxisEnabled, AxisPosOk,
              AxisRef, AxisWarn, AxisError, Lockout, ActPosition, ActVelocity, ActMode, EPosZSW1,
              EPosZSW2, ActWarn, ActFault, Error, Status, DiagID,
              /* internal state */ id_, cmd_status_, cmd_diag_, prev_exec_, prev_ack_, prev_jog_,
              setref_, halting_, sent_velocity_, sent_acc_, sent_dec_, sent_positive_)
  PLC_INTERNAL(id_, cmd_status_, cmd_diag_, prev_exec_, prev_ack_, prev_jog_, setref_, halting_,
               sent_velocity_, sent_acc_, sent_dec_, sent_positive_)

  std::uint32_t id_ = 0;
  std::uint16_t cmd_status_ = 0, cmd_diag_ = 0;  // latched command error
  bool prev_exec_ = false, prev_ack_ = false, prev_jog_ = false;
  bool setref_ = false;
  bool halting_ = false;
  DINT sent_velocity_ = 0;
  INT sent_acc_ = 0, sent_dec_ = 0;
  bool sent_positive_ = false;
};

}  // namespace plc::drive

// AcDrive: speed, run and fault reset of one Toyo VF66B (DNET66-Z) over the
// DeviceNet AC Drive profile assemblies 20/21 -> 70/71, or the VF66B
// extended assemblies 100..108 -> 120..132 / 140 (toyo-vf66-devicenet.md
// §7). One block per drive; it owns the drive's DevicePort. Enable-style:
// Valid while the drive's I/O is usable, Error/ErrorID otherwise.
//
// Configuration (before the first scan): OutputInstance / InputInstance as
// the drive's J-09 / J-10 select them (the port's sizes must match §7.2),
// SpeedScale = the drive's J-11 (0x2A attr 22; read it at start-up with
// AcDriveAttribute rather than assuming 3, §13.2.2), TopSpeed = the drive's
// maximum speed in r/min (20000 counts in the extended assemblies), J12 =
// the drive's J-12 (instance 140's monitor triple), MonitorManualOrder
// (instance 140 monitors 2/3 high byte first, §13.4 item 6).
//
// Commands: RunFwd / RunRev are levels (Run1/Run2 of the event matrix, §5.1;
// Start/Rev in the extended assemblies); both TRUE, or neither, is Stop.
// SpeedRef in r/min (magnitude; the direction comes from RunFwd/RunRev);
// sent as r/min x 2^SpeedScale (§6.1) or as Speed Reference2 = SpeedRef /
// TopSpeed x 20000 (§7.5). NetCtrl / NetRef (instance 21 only) request
// network run control and speed reference; CtrlFromNet / RefFromNet show
// what the drive granted (71 only).
// FaultReset: on its rising edge the block clears the run bits, then sends
// a 0->1 edge on Fault Reset (Fault Reset2 in 100..108) held for
// ResetPulse, then drops it (§13.2.4).
//
// No automatic restart (the manual's own warning, §9.2; ISO 13849-1
// §5.2.2): after a drive fault, a device loss or a fault reset the run bits
// stay 0 (RestartInhibit) until RunFwd and RunRev have both been FALSE once.
//
// Safe state: Enable FALSE, the device not online, or a configuration error
// write run bits 0, fault reset 0 and speed reference 0.
//
// Status: Faulted, Warning, Running (RunningFwd, RunningRev), Ready,
// AtReference, ActualSpeed (r/min), State (§5.2, 71 only; else 0),
// FaultBits (the 32-bit fault field of 120..132, bit n-1 = code n),
// ProtectCode (lowest active code, §7.8; 140 directly, 120..132 from the
// bits; 0 with 70/71, whose profile has no fault code, §5), FaultText
// (Table 6.4), Monitor[0..2] (140: raw monitor data, selected by J12).
// Which outputs an input assembly cannot give stay 0 (see README).
//
// ErrorID (WORD): error_ids.hpp.
#pragma once

#include <array>

#include "plc/fb/acdrive/assemblies.hpp"
#include "plc/io/device_port.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::acdrive {

struct AcDrive {
  // ---------------- configuration ----------------
  io::DevicePort Port;
  USINT OutputInstance = 21;
  USINT InputInstance = 71;
  SINT SpeedScale = 3;
  LREAL TopSpeed = 1800;  // r/min
  USINT J12 = 3;
  BOOL MonitorManualOrder{};
  TIME ResetPulse = std::chrono::milliseconds(100);
  // ---------------- commands ----------------
  BOOL Enable{};
  BOOL RunFwd{};
  BOOL RunRev{};
  BOOL FaultReset{};
  BOOL NetCtrl = true;
  BOOL NetRef = true;
  LREAL SpeedRef{};  // r/min
  // ---------------- status ----------------
  BOOL Valid{};
  BOOL Error{};
  WORD ErrorID{};
  BOOL Faulted{};
  BOOL Warning{};
  BOOL Running{};
  BOOL RunningFwd{};
  BOOL RunningRev{};
  BOOL Ready{};
  BOOL AtReference{};
  BOOL CtrlFromNet{};
  BOOL RefFromNet{};
  DriveState State = DriveState::VendorSpecific;
  LREAL ActualSpeed{};  // r/min, signed
  DWORD FaultBits{};
  USINT ProtectCode{};
  STRING FaultText;
  std::array<UINT, 3> Monitor{};
  BOOL ResetActive{};     // the reset pulse is on the wire
  BOOL RestartInhibit{};  // run bits held 0 until RunFwd/RunRev were FALSE

  void operator()(const ScanContext& ctx);

  PLC_REFLECT(Port, OutputInstance, InputInstance, SpeedScale, TopSpeed, J12, MonitorManualOrder,
              ResetPulse, Enable, RunFwd, RunRev, FaultReset, NetCtrl, NetRef, SpeedRef, Valid,
              Error, ErrorID, Faulted, Warning, Running, RunningFwd, RunningRev, Ready, AtReference,
              CtrlFromNet, RefFromNet, State, ActualSpeed, FaultBits, ProtectCode, FaultText,
              Monitor, ResetActive, RestartInhibit,
              /* internal state */ prev_reset_, reset_phase_, reset_start_, last_ref_, last_ref2_,
              text_code_)
  PLC_INTERNAL(RestartInhibit, prev_reset_, reset_phase_, reset_start_, last_ref_, last_ref2_,
               text_code_)

  // ---- internals ----
  enum class ResetPhase : std::uint8_t { Idle, ClearRun, Pulse };
  [[nodiscard]] bool config_ok() const;
  void read_inputs();
  void write_outputs(bool run_fwd, bool run_rev, bool reset, std::int16_t ref_bus,
                     std::int16_t ref2);
  void write_safe();

  bool prev_reset_ = false;
  ResetPhase reset_phase_ = ResetPhase::Idle;
  TIME reset_start_{};
  std::int16_t last_ref_ = 0;   // last valid SpeedRef on the wire (r/min x 2^SpeedScale)
  std::int16_t last_ref2_ = 0;  // last valid Speed Reference2 (20000 = TopSpeed)
  std::int16_t text_code_ = 0;  // what FaultText shows: protect code, -1 profile fault
};

}  // namespace plc::acdrive

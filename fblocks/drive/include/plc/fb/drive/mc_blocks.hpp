// PLCopen Motion Control Part 1 blocks on a DriveAxis (E1 over telegram 9/111,
// MC_Power and MC_Reset also over telegram 3). Conventions of
// shared/reference/softplc-anchors.md §3:
// * Execute blocks latch their inputs on the rising edge of Execute; exactly
//   one of Busy, Done, Error, CommandAborted is TRUE while Execute is TRUE;
//   Done/Error/CommandAborted/ErrorID reset on the falling edge of Execute and
//   show for at least one scan if the command ends after Execute fell.
// * A command refused in the present axis state gives Error with the state's
//   ErrorID (kErrDisabled, kErrErrorStop, kErrStopping, kErrHoming,
//   kErrNotStandstill); a command replaced by another gives CommandAborted.
// * Enable blocks (MC_Power, MC_Read*) report Valid while Enable is TRUE.
// Units: Position in control units (CU), Velocity in CU/s, Acceleration and
// Deceleration in CU/s^2 (0 = the drive's 100 % ramp Pt534/Pt537). Jerk and
// BufferMode are not supported (always Aborting).
// Setpoints are range-checked against their telegram fields (spec Table
// 3.1.1) on the Execute edge and refused, never wrapped or clamped:
// Position/Distance not finite or outside Int32 (MDI_TARPOS) 16#8024;
// Velocity not finite, <= 0, or outside MDI_VELOCITY 1..2^31-1 (x 1000
// CU/min) 16#8020; Acceleration/Deceleration negative, not finite, above
// 100 % of Pt534/Pt537 (the E1 cannot go faster) or below one MDI_ACC step
// 16#8021.
// ErrorID values: diag_codes.hpp.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>

#include "plc/fb/drive/drive_axis.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::drive {

// PLCopen MC_Direction values used by MC_MoveVelocity.
inline constexpr INT kMcPositiveDirection = 1;
inline constexpr INT kMcNegativeDirection = 3;

// Execute-edge and output-holding logic shared by the Execute blocks.
struct McExecute {
  BOOL Execute{};
  BOOL Done{};
  BOOL Busy{};
  BOOL Active{};
  BOOL CommandAborted{};
  BOOL Error{};
  WORD ErrorID{};

 protected:
  // Returns true on the rising edge of Execute (outputs cleared).
  bool on_call();
  void finish_done();
  void finish_error(std::uint16_t e);
  void finish_aborted();
  // Poll a running axis command; returns true when it ended this scan.
  bool poll(DriveAxis& axis);
  // State check for a new motion command; 0 if allowed.
  static std::uint16_t motion_refusal(const DriveAxis& axis);
  // The call of an idle block (Execute FALSE, not Busy), most calls: all
  // that the blocks using it (MC_Reset, MC_MoveAbsolute, MC_MoveRelative)
  // do then is on_call()'s clearing of the outputs (no edge), as poll() and
  // their Busy branches do nothing while not Busy. Inline in their
  // operator(), so an idle block costs the program no call into the
  // library; false (nothing done) otherwise, and run() makes the call.
  // McIdleCall (test_mc_idle.cpp) compares the two over scripted scans.
  [[gnu::always_inline]] bool idle_call(const ScanContext& ctx, DriveAxis& axis) {
    if (execute_or_busy()) return false;
    axis.begin(ctx);
    Done = Error = CommandAborted = false;
    ErrorID = 0;
    prev_execute_ = false;
    axis.block_done();
    return true;
  }
  // Checks the inputs of a positioning command and starts the task, or
  // finishes with the error that refuses it (MoveAbsolute, MoveRelative).
  void start_positioning(DriveAxis& axis, TaskKind kind, LREAL target, LREAL velocity,
                         LREAL acceleration, LREAL deceleration);

  std::uint32_t id_ = 0;
  bool prev_execute_ = false;

 private:
  // Execute || Busy: the two are bytes 0 and 2 of the block's first word
  // (Execute, Done, Busy, Active: static_asserts below), tested as one
  // load and one test (each byte whole, as the two bool tests).
  [[gnu::always_inline]] bool execute_or_busy() const {
    if constexpr (std::endian::native == std::endian::little) {
      std::uint32_t w;
      std::memcpy(&w, &Execute, sizeof w);
      return (w & 0x00FF00FFu) != 0;
    } else {
      return Execute || Busy;
    }
  }
};
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Winvalid-offsetof"
#endif
static_assert(sizeof(BOOL) == 1);
static_assert(offsetof(McExecute, Execute) == 0 && offsetof(McExecute, Done) == 1 &&
              offsetof(McExecute, Busy) == 2 && offsetof(McExecute, Active) == 3);
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

// MC_Power over STW1/ZSW1: Enable = TRUE walks the drive S1 -> S2 -> S3 -> S4
// (ON = 0 while switch-on inhibited, then ON + enable operation);
// Enable = FALSE takes power away with StopMode 0 = OFF1 ramp (Pt537),
// 1 = OFF2 coast/dynamic brake, 2 = OFF3 quick stop (Pt538 / Pt30A).
// Status = operation enabled (ZSW1.2). Error when the axis has an error or
// S4 is not reached within EnableTimeout (kErrLockout if the drive stayed in
// switch-on inhibited, else kErrEnableTimeout).
// Enable is level-controlled (PLCopen Part 1; the TIA MC_Power does the
// same): after an axis error power stays off, even when the drive answers
// again, until MC_Reset (or SinaPos/SinaSpeed AckError) has acknowledged
// the fault and cleared the error; with Enable still TRUE the block then
// walks the drive from switching on inhibited back to operation by itself
// and the axis goes to Standstill. RequireEnableEdgeAfterReset = TRUE (for
// sites whose rules want a new enable command after every reset) keeps
// power off after the reset as well, with Error and kErrRestartInhibit
// (16#8006), until Enable has been FALSE for a scan and is TRUE again.
// After AbsEncoderInit's own drive reset, Enable held shows 16#8006 until
// MC_Reset (or, with RequireEnableEdgeAfterReset, a new Enable edge).
struct MC_Power {
  BOOL Enable{};
  INT StopMode{0};
  TIME EnableTimeout = std::chrono::seconds(1);
  BOOL RequireEnableEdgeAfterReset{};
  BOOL Status{};
  BOOL Valid{};
  BOOL Error{};
  WORD ErrorID{};

  void operator()(const ScanContext& ctx, DriveAxis& axis);  // inline, below
  PLC_REFLECT(Enable, StopMode, EnableTimeout, RequireEnableEdgeAfterReset, Status, Valid, Error,
              ErrorID, enable_since_, prev_enable_)
  PLC_INTERNAL(enable_since_, prev_enable_)

  TIME enable_since_{};
  bool prev_enable_ = false;
};

// Inline: the block runs every scan while a program powers its axis, and
// as a call into the library it paid its call and register saves each time.
inline void MC_Power::operator()(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  // The steady scan of a powered axis (most scans): Enable with a valid
  // StopMode, the drive answering in operation without a fault, no latched
  // error, no RestartInhibit. Then the general path below gives Status,
  // Valid, no error, the count restarted now and the requests as written
  // here; one test of its conditions instead of the general path's branches
  // (McPower.EqualsTheFormerBlockOverRandomScans compares the two).
  // StopMode 0..2 as one unsigned compare (a negative INT is above 2 so).
  if (Enable && static_cast<std::uint16_t>(StopMode) <= 2 && axis.CommOk &&
      axis.operation_enabled() && !axis.drive_fault() && !axis.CommError && !axis.error_ &&
      !axis.RestartInhibit) [[likely]] {
    axis.PowerRequest = true;
    axis.RequireEnableEdgeAfterReset = RequireEnableEdgeAfterReset;
    axis.PowerStopMode = static_cast<drive::StopMode>(StopMode);
    Status = true;
    prev_enable_ = true;
    enable_since_ = ctx.now;
    Error = false;
    ErrorID = 0;
    Valid = true;
    axis.block_done();
    return;
  }
  const bool mode_ok = StopMode >= 0 && StopMode <= 2;
  axis.PowerRequest = Enable && mode_ok;
  axis.RequireEnableEdgeAfterReset = RequireEnableEdgeAfterReset;
  if (mode_ok) axis.PowerStopMode = static_cast<drive::StopMode>(StopMode);
  Status = axis.CommOk && axis.operation_enabled();
  const std::uint16_t axis_e = axis.axis_error();
  std::uint16_t e = !mode_ok ? kErrMode : axis_e;
  // The error is cleared but the axis still waits for MC_Reset (after
  // AbsEncoderInit's own reset) or, with RequireEnableEdgeAfterReset, for
  // Enable to be given again (DriveAxis::RestartInhibit).
  if (!e && Enable && axis.RestartInhibit) e = kErrRestartInhibit;
  // EnableTimeout counts from the Enable edge, and again from the scan in
  // which nothing holds power off any more: the walk S1 -> S4 after a reset
  // with Enable held is not late. While Status (a powered axis, most
  // scans) the count starts at every scan and there is no timeout, so
  // neither the edge nor what holds power off is asked.
  const bool prev_enable = prev_enable_;
  prev_enable_ = Enable;
  if (Status) {
    enable_since_ = ctx.now;
  } else {
    const bool held_off = axis_e || axis.RestartInhibit || axis.InhibitPower;
    if ((Enable && !prev_enable) || held_off) enable_since_ = ctx.now;
    if (!e && Enable && ctx.now - enable_since_ > EnableTimeout)
      e = axis.drive_state() == DriveState::SwitchingOnInhibited ? kErrLockout : kErrEnableTimeout;
  }
  Error = e != 0;
  ErrorID = e;
  Valid = Enable && !Error;
  axis.block_done();
}

// MC_Reset: its Execute edge starts the axis' reset (DriveAxis::start_reset):
// a new rising edge of STW1.7 for this request (0 first, 1 until the drive
// shows no fault, then 0), and Done once the fault is gone and the drive
// answers: the error is cleared, ErrorStop -> Disabled, and with MC_Power
// Enable held the axis powers up to Standstill (see MC_Power). Every fault
// needs its own MC_Reset edge. Error with kErrResetTimeout if the fault is
// still there after Timeout (its cause is not gone), or the communication
// error if the drive does not answer; the axis stays in ErrorStop.
struct MC_Reset : McExecute {
  TIME Timeout = std::chrono::seconds(1);
  void operator()(const ScanContext& ctx, DriveAxis& axis) {
    if (!idle_call(ctx, axis)) run(ctx, axis);
  }
  // The whole call, whatever the state (out of line; operator() makes it
  // unless the block is idle).
  void run(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(Execute, Timeout, Done, Busy, Error, ErrorID, id_, prev_execute_)
  PLC_INTERNAL(id_, prev_execute_)
};

struct MC_MoveAbsolute : McExecute {
  LREAL Position{};
  LREAL Velocity{};
  LREAL Acceleration{};
  LREAL Deceleration{};
  void operator()(const ScanContext& ctx, DriveAxis& axis) {
    if (!idle_call(ctx, axis)) run(ctx, axis);
  }
  // The whole call, whatever the state (out of line; operator() makes it
  // unless the block is idle).
  void run(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(Execute, Position, Velocity, Acceleration, Deceleration, Done, Busy, Active,
              CommandAborted, Error, ErrorID, id_, prev_execute_)
  PLC_INTERNAL(id_, prev_execute_)
};

struct MC_MoveRelative : McExecute {
  LREAL Distance{};
  LREAL Velocity{};
  LREAL Acceleration{};
  LREAL Deceleration{};
  void operator()(const ScanContext& ctx, DriveAxis& axis) {
    if (!idle_call(ctx, axis)) run(ctx, axis);
  }
  // The whole call, whatever the state (out of line; operator() makes it
  // unless the block is idle).
  void run(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(Execute, Distance, Velocity, Acceleration, Deceleration, Done, Busy, Active,
              CommandAborted, Error, ErrorID, id_, prev_execute_)
  PLC_INTERNAL(id_, prev_execute_)
};

// The E1 has no speed-controlled MDI submode (spec §7.6): MC_MoveVelocity
// sends a relative task to the far end of the 32-bit range (about 2^31 CU)
// at Velocity, which runs until another command takes over. InVelocity when
// the actual velocity is within 1 % of Velocity x override.
struct MC_MoveVelocity : McExecute {
  LREAL Velocity{};
  LREAL Acceleration{};
  LREAL Deceleration{};
  INT Direction = kMcPositiveDirection;
  BOOL InVelocity{};
  void operator()(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(Execute, Velocity, Acceleration, Deceleration, Direction, InVelocity, Busy, Active,
              CommandAborted, Error, ErrorID, id_, prev_execute_)
  PLC_INTERNAL(id_, prev_execute_)
};

// Drive-internal homing (STW1.11, spec §7.8): Done when ZSW1.11 (home set)
// is back after the drive started homing and the motor stands. Position is
// not sent: the E1 takes its home position from its own parameters; it must
// still be a valid target (finite, Int32), else 16#8024. Only from
// Standstill.
struct MC_Home : McExecute {
  LREAL Position{};
  TIME Timeout = std::chrono::seconds(60);
  void operator()(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(Execute, Position, Timeout, Done, Busy, Active, CommandAborted, Error, ErrorID, id_,
              prev_execute_)
  PLC_INTERNAL(id_, prev_execute_)
};

// MC_Stop: rejects the traversing task (STW1.4 = 0: the drive stops with
// its emergency ramp Pt538) and stops jog and homing. Done at standstill;
// the axis stays in Stopping, refusing motion, while Execute is TRUE.
// Deceleration is not sent (the E1 has no per-command stop ramp).
struct MC_Stop : McExecute {
  LREAL Deceleration{};
  void operator()(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(Execute, Deceleration, Done, Busy, Active, CommandAborted, Error, ErrorID, id_,
              prev_execute_, held_)
  PLC_INTERNAL(id_, prev_execute_, held_)
  bool held_ = false;
};

// MC_Halt: intermediate stop (STW1.5 = 0) on the task's own deceleration,
// then drops the task at standstill. Another motion command may abort it.
struct MC_Halt : McExecute {
  LREAL Deceleration{};
  void operator()(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(Execute, Deceleration, Done, Busy, Active, CommandAborted, Error, ErrorID, id_,
              prev_execute_)
  PLC_INTERNAL(id_, prev_execute_)
};

struct MC_ReadStatus {
  BOOL Enable{};
  BOOL Valid{}, Busy{}, Error{};
  WORD ErrorID{};
  BOOL ErrorStop{}, Disabled{}, Stopping{}, Homing{}, Standstill{}, DiscreteMotion{},
      ContinuousMotion{}, SynchronizedMotion{};
  void operator()(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(Enable, Valid, Busy, Error, ErrorID, ErrorStop, Disabled, Stopping, Homing,
              Standstill, DiscreteMotion, ContinuousMotion, SynchronizedMotion)
};

struct MC_ReadActualPosition {
  BOOL Enable{};
  BOOL Valid{}, Busy{}, Error{};
  WORD ErrorID{};
  LREAL Position{};
  void operator()(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(Enable, Valid, Busy, Error, ErrorID, Position)
};

// PLCopen dynamics (CU/s^2) -> MDI_ACC/MDI_DEC: 0 = the drive's 100 % ramp;
// std::nullopt (kErrAccel) for a value that is negative, not finite, above
// 100 % of Pt534/Pt537 or below the field's smallest step.
std::optional<INT> accel_to_mdi(const DriveAxis& axis, LREAL accel, bool deceleration);

}  // namespace plc::drive

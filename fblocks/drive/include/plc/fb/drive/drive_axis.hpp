// DriveAxis: the PLC's handle on one E1 drive (PLCopen AXIS_REF), the layer
// between the PROFIdrive telegram types and the blocks (RTmotion's layering:
// blocks -> axis state and commands -> drive words).
//
// Every block on a drive takes the same DriveAxis (`fb(ctx, axis)`). The
// axis
// * reads the drive's telegram once per scan (begin(), idempotent per scan)
//   and writes the PLC's telegram after every block (commit()), so the
//   order of the blocks in a program does not matter; a program that calls
//   several blocks on one axis may instead write it once per scan itself
//   (set_program_commits(), below);
// * counts the controller sign-of-life into STW2.12-15 once per scan and
//   watches the drive's in ZSW2.12-15: a counter that does not move for more
//   than SignOfLifeTolerance scans (like PNU 925 on the drive side) is a
//   loss of sign-of-life, and every block on the axis reports kErrSignOfLife
//   until MC_Reset (or AckError) once the counter runs again; while the
//   device is offline the monitoring starts over (the next connection
//   counts anew), the latched axis error stays;
// * runs the traversing-task handshake of spec §7.6/§10.1: STW1.6 is raised
//   only after ZSW1.12 was seen 0, held until ZSW1.12 rises (the drive's
//   acknowledgement, "rising edge active"), then dropped; the task is done
//   when ZSW1.10 (target reached) is 1 after the acknowledgement. No
//   acknowledgement within AckTimeout is kErrTaskNotAck;
// * keeps the PLCopen axis state (Disabled, Standstill, Homing,
//   DiscreteMotion, ContinuousMotion, Stopping, ErrorStop) and the id of the
//   command in control, so a block whose command was replaced reports
//   CommandAborted.
//
// Safe state: while the drive is not reachable or the sign-of-life is lost,
// STW1 goes to OFF1 (0x0406: control by PLC, no OFF2/OFF3, ON = 0).
//
// Restart after an error (PLCopen MC Part 1 state diagram: ErrorStop is left
// only through MC_Reset, which leads to Standstill if power is enabled;
// ISO 13849-1 §5.2.2: a reset must not start the machine by itself, so the
// reset has to be an explicit act). Every axis error (communication lost,
// sign-of-life, drive fault) sets RestartInhibit, and while it is set, or
// the axis is in ErrorStop, commit() never asks for power (ON and enable
// operation stay 0), even when the drive answers again. An explicit reset
// (start_reset(): MC_Reset's Execute edge, SinaPos/SinaSpeed's AckError
// edge) acknowledges the drive with a new STW1.7 edge and, once the drive
// shows no fault and answers, clears the error and ends RestartInhibit: a
// power request still held (MC_Power Enable, EnableAxis) walks the drive
// from switching on inhibited (S1: OFF1 first) back to operation, as the
// TIA motion blocks do. With RequireEnableEdgeAfterReset (set by the power
// block) RestartInhibit ends instead only once the error is cleared AND the
// power request was withdrawn (e.g. Enable FALSE for a scan), so the next
// Enable edge powers the drive. AbsEncoderInit clears the communication
// error its own 3215h reset caused, but not RestartInhibit.
#pragma once

#include <cstdint>

#include "plc/fb/drive/diag_codes.hpp"
#include "plc/fb/drive/telegrams.hpp"
#include "plc/io/device_port.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::drive {

// PLCopen axis states (PLCopen MC Part 1 §3.2 diagram; numbered in the
// diagram's order).
enum class AxisState : std::uint8_t {
  Disabled = 0,
  Standstill = 1,
  Homing = 2,
  DiscreteMotion = 3,
  ContinuousMotion = 4,
  SynchronizedMotion = 5,  // not used by these blocks
  Stopping = 6,
  ErrorStop = 7,
};
const char* to_string(AxisState s);

// PROFIdrive drive state as read from ZSW1 (spec §5).
enum class DriveState : std::uint8_t {
  SwitchingOnInhibited = 1,  // S1
  ReadyForSwitchingOn = 2,   // S2
  SwitchedOn = 3,            // S3
  Operation = 4,             // S4
  SwitchingOff = 5,          // S5 (OFF1 or OFF3 branch)
  Fault = 6,
};
DriveState drive_state_from_zsw1(std::uint16_t zsw1);

// How power is taken away (MC_Power StopMode, SinaPos ConfigEPos).
enum class StopMode : std::uint8_t { Off1Ramp = 0, Off2Coast = 1, Off3Quick = 2 };

// Kinds of traversing task the axis sends over telegram 9/111.
enum class TaskKind : std::uint8_t { Relative = 1, Absolute = 2, Velocity = 3 };

enum class CmdStatus : std::uint8_t { Busy, Done, Aborted, Error };

// How long an AckError edge (SinaPos, SinaSpeed) waits for the drive's fault
// to go before the acknowledge is dropped: MC_Reset's default Timeout.
inline constexpr TIME kAckErrorTimeout = std::chrono::seconds(1);

struct DriveAxis {
  // ---------------- configuration (before the first scan) ----------------
  io::DevicePort Port;
  UINT Telegram = 111;           // 3, 9 or 111, as configured in the drive
  UINT SignOfLifeTolerance = 5;  // scans the drive counter may stand still
  BOOL SignOfLifeCheck = true;
  LREAL CuPerRev = 10000;    // control units per motor revolution
  LREAL RefSpeedRpm = 3000;  // Pt317 (100 % of NSOLL_B/NIST_B)
  LREAL AccTimeMs = 100;     // Pt534: 100 % MDI_ACC, 0 -> RefSpeed
  LREAL DecTimeMs = 100;     // Pt537: 100 % MDI_DEC
  TIME AckTimeout = std::chrono::milliseconds(200);

  // ---------------- actual values (each scan) ----------------
  WORD ZSW1{}, ZSW2{}, POS_ZSW1{}, POS_ZSW2{}, MELDW{}, AKTSATZ{}, G1_ZSW{};
  DINT XIST_A{}, NIST_B{};
  UDINT G1_XIST1{}, G1_XIST2{};
  UINT FAULT_CODE{}, WARN_CODE{};
  LREAL ActPosition{};  // CU (XIST_A; G1_XIST1 on telegram 3)
  LREAL ActVelocity{};  // CU/s from NIST_B (telegram 3/111) or XIST_A difference (9)
  BOOL CommOk{};        // online, right telegram, sign-of-life alive
  BOOL SignOfLifeLost{};
  WORD CommError{};  // kErrOffline / kErrSignOfLife / kErrTelegram or 0
  AxisState State = AxisState::Disabled;
  // Set by any axis error; power is refused until an explicit reset (or,
  // with RequireEnableEdgeAfterReset, until the error is cleared and
  // PowerRequest has been FALSE once after that; see the header comment).
  BOOL RestartInhibit{};

  // ---------------- sent to the drive (composed by commit()) ----------------
  WORD STW1{}, STW2{}, POS_STW1{}, POS_STW2{}, SATZANW{}, MDI_MODE{}, G1_STW{};
  UINT OVERRIDE = 0x4000;
  DINT MDI_TARPOS{}, MDI_VELOCITY{}, NSOLL_B{};
  INT MDI_ACC = 0x4000, MDI_DEC = 0x4000;

  // ---------------- requests from blocks ----------------
  BOOL PowerRequest{};  // MC_Power / SinaPos / SinaSpeed enable
  StopMode PowerStopMode = StopMode::Off1Ramp;
  BOOL AckRequest{};  // STW1.7, driven by the reset procedure (start_reset())
  // From the power block (MC_Power, SinaPos, SinaSpeed): TRUE keeps power off
  // after a reset until the power request was withdrawn once.
  BOOL RequireEnableEdgeAfterReset{};
  BOOL JogRequest1{}, JogRequest2{};
  BOOL IntermediateStop{};     // STW1.5 = 0 while TRUE
  BOOL RejectTask{};           // STW1.4 = 0 while TRUE
  BOOL StopActive{};           // MC_Stop holds the axis in Stopping
  BOOL SetReferenceRequest{};  // POS_STW2.1
  BOOL InhibitPower{};         // AbsEncoderInit: force OFF1 whatever PowerRequest says

  // ---------------- the scan protocol ----------------
  // Read inputs once per scan: every block calls it, the first of a scan
  // does the work (the check is inline, it is the common case).
  void begin(const ScanContext& ctx) {
    if (begun_ && ctx.cycle == last_cycle_ && ctx.now == now_) return;
    begin_scan(ctx);
  }
  void commit();  // write outputs (cheap, any number of times)
  // What every block calls after its work: commit(), unless the program
  // writes the telegram itself.
  void block_done() {
    if (!program_commits_) commit();
  }
  // Who writes the PLC's telegram, set before the first scan. false (the
  // default): every block, after its call (block_done()). true: the blocks
  // leave it, and the program calls commit() once per scan after the last
  // block on this axis; only that last write reaches the drive anyway, so
  // a program with several blocks on one axis saves the writes before it.
  // Between the blocks of a scan the axis then shows the words of the last
  // scan (STW1, stw6_sent_: what the drive has seen), and a change the
  // program makes after its last block goes out in this scan, not the next.
  // A program that does not commit in a scan stops the controller
  // sign-of-life and the drive trips (AL.FB1), so this is not a variable:
  // the program's structure decides it, neither the debugger nor the HMI.
  void set_program_commits(bool on) { program_commits_ = on; }
  [[nodiscard]] bool program_commits() const { return program_commits_; }

  [[nodiscard]] TelegramType telegram() const { return static_cast<TelegramType>(Telegram); }
  [[nodiscard]] bool positioning() const { return Telegram == 9 || Telegram == 111; }
  [[nodiscard]] DriveState drive_state() const { return drive_state_from_zsw1(ZSW1); }
  [[nodiscard]] bool operation_enabled() const { return (ZSW1 & Zsw1Pos::kOperationEnabled) != 0; }
  [[nodiscard]] bool drive_fault() const { return (ZSW1 & Zsw1Pos::kFault) != 0; }
  [[nodiscard]] bool standstill() const { return (ZSW1 & Zsw1Pos::kMotorStopped) != 0; }
  [[nodiscard]] bool homed() const { return (ZSW1 & Zsw1Pos::kHomePositionSet) != 0; }
  [[nodiscard]] bool target_reached() const { return (ZSW1 & Zsw1Pos::kTargetReached) != 0; }
  // The error every block on this axis reports now (0 = none): comm first,
  // then a drive fault, then a latched axis error (ErrorStop).
  [[nodiscard]] std::uint16_t axis_error() const {
    if (CommError) return CommError;
    if (drive_fault()) return kErrDriveFault;
    return error_;
  }
  [[nodiscard]] TIME now() const { return now_; }

  // ---- command interface for blocks (PLCopen layer) ----
  // Each start returns the id of the new command; the previous command is
  // aborted. A block polls status(id) in later scans.
  std::uint32_t start_task(TaskKind kind, DINT position, DINT mdi_velocity, INT mdi_acc,
                           INT mdi_dec);
  std::uint32_t start_homing(TIME timeout);
  std::uint32_t start_stop();       // MC_Stop: reject task, jog off, hold Stopping
  std::uint32_t start_halt();       // MC_Halt: intermediate stop, then drop the task
  std::uint32_t start_jog();        // jog via JogRequest1/2 levels
  void end_stop(std::uint32_t id);  // MC_Stop released (Execute FALSE)
  void release(std::uint32_t id);   // a continuous command lets go (jog off)
  [[nodiscard]] CmdStatus status(std::uint32_t id) const;
  [[nodiscard]] std::uint16_t cmd_error(std::uint32_t id) const;
  [[nodiscard]] bool in_velocity(std::uint32_t id) const;
  [[nodiscard]] std::uint32_t active_command() const { return cmd_id_; }
  void abort_all();  // power off / ErrorStop: nothing in control
  void latch_error(std::uint16_t e) {
    if (!error_) error_ = e;
  }
  // Clear the latched error and the sign-of-life loss (ErrorStop ->
  // Disabled); RestartInhibit is left as it is.
  void reset_errors();

  // ---- explicit reset (MC_Reset Execute edge, SinaPos/SinaSpeed AckError edge) ----
  // Restarts the sign-of-life monitoring and sends the drive a new STW1.7
  // edge: 0 until the drive has answered once (its sign-of-life moved, so
  // it has seen the 0), then 1 until ZSW1.3 shows no fault, then 0. The
  // reset is Done once the drive shows no fault, the communication is good
  // and the drive's sign-of-life has moved since the request: the error is
  // cleared and, unless RequireEnableEdgeAfterReset, RestartInhibit ends.
  // It fails after `timeout` (reset_error(): kErrResetTimeout while the
  // fault persists, else the communication error); the error stays latched.
  // A new request during a running one starts over (a new 0 -> 1 edge).
  enum class ResetStatus : std::uint8_t { Idle, Busy, Done, Error };
  void start_reset(TIME timeout);
  [[nodiscard]] ResetStatus reset_status() const;
  [[nodiscard]] std::uint16_t reset_error() const { return reset_err_; }
  [[nodiscard]] std::uint8_t drive_sign_of_life() const {
    return static_cast<std::uint8_t>((ZSW2.value >> 12) & 0xF);
  }

  PLC_REFLECT(Port, Telegram, SignOfLifeTolerance, SignOfLifeCheck, CuPerRev, RefSpeedRpm,
              AccTimeMs, DecTimeMs, AckTimeout, ZSW1, ZSW2, POS_ZSW1, POS_ZSW2, MELDW, AKTSATZ,
              G1_ZSW, XIST_A, NIST_B, G1_XIST1, G1_XIST2, FAULT_CODE, WARN_CODE, ActPosition,
              ActVelocity, CommOk, SignOfLifeLost, CommError, State, RestartInhibit, STW1, STW2,
              POS_STW1, POS_STW2, SATZANW, MDI_MODE, G1_STW, OVERRIDE, MDI_TARPOS, MDI_VELOCITY,
              NSOLL_B, MDI_ACC, MDI_DEC, PowerRequest, PowerStopMode, AckRequest, JogRequest1,
              JogRequest2, IntermediateStop, RejectTask, StopActive, SetReferenceRequest,
              InhibitPower, RequireEnableEdgeAfterReset,
              // internal state: shown by the debugger, kept in recording snapshots
              now_, last_scan_, last_cycle_, begun_, sol_out_, sol_in_last_, sol_stall_, sol_seen_,
              error_, cmd_id_, next_id_, kind_, phase_, task_kind_, cmd_err_, phase_start_,
              homing_timeout_, stw6_, stw6_sent_, homing_bit_, homing_started_, seen_traversing_,
              halt_release_, prev_xist_, have_prev_xist_, task_velocity_, reset_phase_,
              reset_start_, reset_timeout_, reset_scans_, reset_err_, reset_sol_, reset_answered_)
  // State too: the PLCopen state machine runs on it; and RestartInhibit, the
  // interlock against a restart without an explicit reset.
  PLC_INTERNAL(State, RestartInhibit, now_, last_scan_, last_cycle_, begun_, sol_out_, sol_in_last_,
               sol_stall_, sol_seen_, error_, cmd_id_, next_id_, kind_, phase_, task_kind_,
               cmd_err_, phase_start_, homing_timeout_, stw6_, stw6_sent_, homing_bit_,
               homing_started_, seen_traversing_, halt_release_, prev_xist_, have_prev_xist_,
               task_velocity_, reset_phase_, reset_start_, reset_timeout_, reset_scans_, reset_err_,
               reset_sol_, reset_answered_)

  // ---- internals (public for tests and the benchmark, not for programs) ----
  enum class Phase : std::uint8_t { Idle, PreLow, Request, Running, Done, Error, Aborted };
  enum class Kind : std::uint8_t { None, Task, Homing, Stop, Halt, Jog };
  enum class ResetPhase : std::uint8_t { Idle, AckLow, AckHigh, Done, Error };
  void begin_scan(const ScanContext& ctx);  // begin()'s work, once per scan
  void advance();
  void advance_reset();
  void update_state();
  void open_command(Kind kind, Phase phase);

  TIME now_{};
  TIME last_scan_{};
  std::uint64_t last_cycle_ = ~std::uint64_t{0};
  bool begun_ = false;
  std::uint8_t sol_out_ = 0, sol_in_last_ = 0;
  std::uint16_t sol_stall_ = 0;
  bool sol_seen_ = false;
  std::uint16_t error_ = 0;  // latched axis error (ErrorStop until reset)
  std::uint32_t cmd_id_ = 0, next_id_ = 1;
  Kind kind_ = Kind::None;
  Phase phase_ = Phase::Idle;
  TaskKind task_kind_ = TaskKind::Relative;
  std::uint16_t cmd_err_ = 0;
  TIME phase_start_{};
  TIME homing_timeout_{};
  bool stw6_ = false, stw6_sent_ = false, homing_bit_ = false, homing_started_ = false;
  bool seen_traversing_ = false, halt_release_ = false;
  DINT prev_xist_ = 0;
  bool have_prev_xist_ = false;
  DINT task_velocity_ = 0;
  ResetPhase reset_phase_ = ResetPhase::Idle;
  TIME reset_start_{};
  TIME reset_timeout_{};
  std::uint16_t reset_scans_ = 0;
  std::uint16_t reset_err_ = 0;
  std::uint8_t reset_sol_ = 0;  // the drive's sign-of-life when the reset was requested
  bool reset_answered_ = false;
  bool program_commits_ = false;  // not reflected: see set_program_commits()
};

}  // namespace plc::drive

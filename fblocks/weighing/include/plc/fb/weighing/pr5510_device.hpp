// PR5510_Device: one PR5510's windows, shared by several blocks.
//
// Like a PLCopen AXIS_REF, one instance stands for one device; the blocks
// that use the device (PR5510_ReadValue, _WriteValue, _Command,
// _DigitalOutputs, _Status, _BatchWeigh) get a pointer to it in their
// `Device` input. Call it once per scan BEFORE those blocks (called after
// them it still works, with one scan more latency).
//
// Call the device and all its blocks from one task (the arbitration state
// is not shared between threads).
//
// Why a shared owner: the windows have one Read_Value_Select byte, one
// Write_Value_Select byte with its Write_Active handshake and one command
// byte, so two blocks writing them directly would step on each other.
//
// Arbitration (documented contract):
//  * Read window. A block requests a code on every call while it wants it
//    (a block that is not called loses its request). One block at a time
//    holds the window; the grant goes round-robin over the slots. The holder
//    keeps it while it wants it and nobody else waits; when others wait, it
//    passes on after the holder has seen its value for at least one scan.
//    A holder whose code is not echoed within EchoTimeout gets
//    kReadEchoTimeout. Urgent requests (PR5510_BatchWeigh while a feed
//    valve is open: its cut-off needs every 20 ms value) go first and are
//    not rotated away; the other readers wait for them without timing out
//    (the echo timeout runs from the grant). Going back to a code still echoed is valid at once
//    (spec §7.2 Read(code) step 6).
//  * Write window. Requests queue per slot and run one at a time,
//    round-robin; the device itself runs the whole Write_Active handshake
//    (spec §3.6 / §7.2 Write), so an unfinished handshake never blocks the
//    window, even if the requesting block stops being called.
//  * Commands (W[7]). One command bit is pulsed at a time, held CommandHold
//    (>= 40 ms, spec §3.3), then held low CommandHold before the next pulse,
//    so conflicting bits never share one edge (spec §7.2).
//  * Digital outputs (W[6]). Level bits; the last block that sets an
//    output bit in a scan wins, so give every output one owner.
//  * The device reads full scale (0x0E, which clears Cal_Changed), format
//    (0x04) and model (0x05) itself when it comes online and whenever
//    Cal_Changed rises (spec §7.2 start-up), and re-reads code 4 when
//    Cmd_Error rises to learn the device error number (ErrorID 16#81nn).
#pragma once

#include <array>
#include <bit>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <span>

#include "plc/fb/weighing/error_ids.hpp"
#include "plc/fb/weighing/window_codec.hpp"
#include "plc/io/device_port.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::weighing {

using namespace std::chrono_literals;

enum class WriteStatus : std::uint8_t { Idle, Pending, Active, Done, Error };
enum class CommandStatus : std::uint8_t { Idle, Pending, Active, Done, Error };

class PR5510_Device {
 public:
  static constexpr int kMaxClients = 8;  // slot 0 is the device's own reader (bit masks: <= 8)
  static constexpr int kNoSlot = -1;

  // ---- inputs ----
  io::DevicePort port;
  Bus BusType = Bus::Profibus;                          // byte order of bytes 0..3 (spec §3)
  PackedOrder PackedWordOrder = PackedOrder::MsbFirst;  // [AMBIG] 9, see codec
  TIME EchoTimeout = 500ms;                             // spec §7.2: 200-500 ms
  TIME WriteTimeout = 5s;   // per handshake phase; tare may wait for standstill
  TIME CommandHold = 60ms;  // >= 40 ms (shorter values count as 40 ms); 60 ms spans three cycles
  // Spec §7.2 Write step 3: with a consistent module (0xB7/0xF3, or
  // DeviceNet) value and code go in one telegram; with a "Seperate" module
  // the value goes first and the code one device cycle (20 ms) later.
  BOOL ConsistentModule = true;

  // ---- outputs ----
  BOOL Online{};      // port bound and device Online
  BOOL Ready{};       // full scale and format known
  BYTE StatusByte{};  // R[5], R[6], R[7] as read this scan
  BYTE CommandByte{};
  BYTE WeighingByte{};
  DINT FullScale{};  // code 0x0E, display digits
  USINT Decimals{};  // code 4
  USINT Unit{};
  USINT Division{};
  USINT LastError{};  // code 4, last displayed error (spec §5.3)
  UINT Model{};       // code 5
  UINT Version{};
  UDINT FormatReads{};  // completed reads of code 4 (tests, diagnostics)
  SINT ReadHolder{-1};  // slot holding the read window, -1 = none
  UDINT ReadGrants{};   // grants given (arbitration diagnostics)

  PLC_REFLECT(port, BusType, PackedWordOrder, EchoTimeout, WriteTimeout, CommandHold,
              ConsistentModule, Online, Ready, StatusByte, CommandByte, WeighingByte, FullScale,
              Decimals, Unit, Division, LastError, Model, Version, FormatReads, ReadHolder,
              ReadGrants,
              // internal state (status_ is decoded afresh from the window every scan)
              prev_cal_changed_, prev_cmd_error_, was_online_, clients_, scale_, rd_req_, rd_err_,
              rd_urgent_, wr_pending_, cmd_pending_, rd_code_, read_error_, holder_, holder_code_,
              holder_served_, grant_time_, want_fsd_, want_format_, want_model_, wr_status_,
              wr_error_, wr_code_, wr_raw_, wr_phase_, wr_slot_, wr_next_, wr_cmd_error_, wr_epoch_,
              wr_since_, cmd_status_, cmd_error_, cmd_bit_, cmd_phase_, cmd_slot_, cmd_next_,
              cmd_epoch_, cmd_since_, outputs_)
  // ReadHolder too: the round-robin goes on from it.
  PLC_INTERNAL(ReadHolder, prev_cal_changed_, prev_cmd_error_, was_online_, clients_, scale_,
               rd_req_, rd_err_, rd_urgent_, wr_pending_, cmd_pending_, rd_code_, read_error_,
               holder_, holder_code_, holder_served_, grant_time_, want_fsd_, want_format_,
               want_model_, wr_status_, wr_error_, wr_code_, wr_raw_, wr_phase_, wr_slot_, wr_next_,
               wr_cmd_error_, wr_epoch_, wr_since_, cmd_status_, cmd_error_, cmd_bit_, cmd_phase_,
               cmd_slot_, cmd_next_, cmd_epoch_, cmd_since_, outputs_)

  // Inline (scan<true>() below): the programs' cycle() takes the scan
  // without a call, its register saves and frame; the rare work (offline,
  // own reads, writes, commands, status decode) stays out of line.
  void operator()(const ScanContext& ctx) { scan<true>(ctx); }
  // operator() without its steady read path (tests compare the two).
  void scan_general(const ScanContext& ctx);

  // ---- client side (the other weighing blocks) ----
  // A slot for one block, or kNoSlot when all are taken.
  int attach();

  // Read window: call on every scan while the value is wanted. `urgent`
  // requests (a batch while its valves are open) are served before the
  // others and keep the window while they last.
  void request_read(int slot, std::uint8_t code, bool urgent = false) {
    if (!valid(slot)) return;
    rd_req_ = static_cast<std::uint8_t>(rd_req_ | bit(slot));
    if (urgent) rd_urgent_ = static_cast<std::uint8_t>(rd_urgent_ | bit(slot));
    rd_code_[idx(slot)] = code;
  }
  // The read window carries `code` for this slot now (granted, echoed).
  [[nodiscard]] bool read_valid(int slot, std::uint8_t code) const {
    // Spec §3.5: the value belongs to `code` once R[4] echoes it; the window
    // must be ours so that W[4] keeps that code.
    return Online && holder_ == slot && holder_code_ == code &&
           port.in()[r::kReadValueSelected] == code;
  }
  // Set when this slot's code was not echoed in time; cleared when the slot
  // stops requesting.
  // A slot outside 0..kMaxClients-1 (a block that holds none: kNoSlot) has
  // error kNoJob, and its writes and commands fail with it.
  [[nodiscard]] std::uint16_t read_error(int slot) const {
    return valid(slot) ? read_error_[idx(slot)] : error_id::kNoJob;
  }
  [[nodiscard]] DINT read_dint() const { return decode_dint(port.in(), BusType); }
  [[nodiscard]] REAL read_real() const { return decode_real(port.in(), BusType); }
  [[nodiscard]] std::uint32_t read_raw() const { return decode_raw(port.in(), BusType); }

  // Write window: queue one write; false if this slot already has one.
  bool request_write(int slot, std::uint8_t code, std::uint32_t raw);
  [[nodiscard]] WriteStatus write_status(int slot) const {
    return valid(slot) ? wr_status_[idx(slot)] : WriteStatus::Error;
  }
  [[nodiscard]] std::uint16_t write_error(int slot) const {
    return valid(slot) ? wr_error_[idx(slot)] : error_id::kNoJob;
  }
  void ack_write(int slot);  // collect Done/Error (or cancel a Pending one)

  // Commands: queue one W[7] pulse; false if this slot already has one.
  bool request_command(int slot, CommandBit command);
  [[nodiscard]] CommandStatus command_status(int slot) const {
    return valid(slot) ? cmd_status_[idx(slot)] : CommandStatus::Error;
  }
  [[nodiscard]] std::uint16_t command_error(int slot) const {
    return valid(slot) ? cmd_error_[idx(slot)] : error_id::kNoJob;
  }
  void ack_command(int slot);

  // Digital outputs 1..3 (W[6], level).
  void set_output(OutputBit b, bool on) {
    const auto m = static_cast<std::uint8_t>(1U << static_cast<unsigned>(b));
    set_outputs(m, on ? m : std::uint8_t{0});
  }
  // Outputs 1..3 at once: the bits of `mask` take those of `values`, the
  // others stay (the byte set_output() would leave after one call per bit).
  void set_outputs(std::uint8_t mask, std::uint8_t values) {
    outputs_ = static_cast<std::uint8_t>((outputs_ & ~mask) | (values & mask));
    // Written at once so that a valve closes in the scan that decides it.
    if (port.bound() && port.out().size() >= kWindowSize) port.out()[w::kOutputs] = outputs_;
  }

  [[nodiscard]] const StatusBits& status() const { return status_; }
  // Weight digits -> display units (kg, g, ...) using code 4's decimals.
  [[nodiscard]] REAL to_units(DINT digits) const { return static_cast<REAL>(digits) / scale_; }
  [[nodiscard]] TIME command_hold() const {
    return CommandHold < std::chrono::milliseconds(kCommandHoldMinMs)
               ? TIME(std::chrono::milliseconds(kCommandHoldMinMs))
               : CommandHold;
  }

 private:
  enum class WrPhase : std::uint8_t { Idle, WaitFree, PutCode, WaitAck, WaitRelease, WaitErrorNo };
  enum class CmdPhase : std::uint8_t { Idle, High, WaitDone, WaitErrorNo, Gap };

  static bool valid(int slot) { return slot >= 0 && slot < kMaxClients; }
  static std::size_t idx(int slot) { return static_cast<std::size_t>(slot); }
  static std::uint8_t bit(int slot) { return static_cast<std::uint8_t>(1U << slot); }
  // First slot at or after `from` (round-robin) whose bit is set in mask.
  static int next_in(std::uint8_t mask, int from);
  static constexpr int kOwnSlot = 0;  // the device's own reader
  // decode_status() where the status bytes changed (a few scans in a
  // hundred): out of line, so that the inline scan needs fewer registers.
  [[gnu::noinline]] static StatusBits decode_status_changed(std::span<const std::uint8_t> in);
  void go_offline();
  void run_own_reader();
  // operator()'s work; SteadyRead false: scan_general().
  template <bool SteadyRead>
  [[gnu::always_inline]] inline void scan(const ScanContext& ctx);
  // Called from scan() alone, every scan: inline, no call and no register
  // saves.
  template <bool SteadyRead>
  [[gnu::always_inline]] inline void arbitrate_read(TIME now);
  void run_write(TIME now);
  void run_command(TIME now);
  void finish_write(std::uint16_t err);
  void finish_command(std::uint16_t err);

  StatusBits status_{};           // decode_status() of status_raw_
  std::uint32_t status_raw_ = 0;  // R[5] | R[6] << 8 | R[7] << 16 last decoded
  bool prev_cal_changed_ = false, prev_cmd_error_ = false, was_online_ = false;
  int clients_ = 1;
  float scale_ = 1.0f;

  // read window
  std::uint8_t rd_req_ = 0;       // bit per slot: requested since the last call
  std::uint8_t rd_err_ = 0;       // bit per slot: read_error_ set
  std::uint8_t rd_urgent_ = 0;    // bit per slot: urgent request
  std::uint8_t wr_pending_ = 0;   // bit per slot: WriteStatus::Pending
  std::uint8_t cmd_pending_ = 0;  // bit per slot: CommandStatus::Pending
  std::array<std::uint8_t, kMaxClients> rd_code_{};
  std::array<std::uint16_t, kMaxClients> read_error_{};
  int holder_ = kNoSlot;
  std::uint8_t holder_code_ = 0;
  bool holder_served_ = false;
  TIME grant_time_{};
  // the device's own reader (slot 0)
  bool want_fsd_ = false, want_format_ = false, want_model_ = false;

  // write window
  std::array<WriteStatus, kMaxClients> wr_status_{};
  std::array<std::uint16_t, kMaxClients> wr_error_{};
  std::array<std::uint8_t, kMaxClients> wr_code_{};
  std::array<std::uint32_t, kMaxClients> wr_raw_{};
  WrPhase wr_phase_ = WrPhase::Idle;
  int wr_slot_ = kNoSlot;
  int wr_next_ = 0;
  bool wr_cmd_error_ = false;
  UDINT wr_epoch_ = 0;
  TIME wr_since_{};

  // commands
  std::array<CommandStatus, kMaxClients> cmd_status_{};
  std::array<std::uint16_t, kMaxClients> cmd_error_{};
  std::array<CommandBit, kMaxClients> cmd_bit_{};
  CmdPhase cmd_phase_ = CmdPhase::Idle;
  int cmd_slot_ = kNoSlot;
  int cmd_next_ = 0;
  UDINT cmd_epoch_ = 0;
  TIME cmd_since_{};

  std::uint8_t outputs_ = 0;
};

template <bool SteadyRead>
inline void PR5510_Device::scan(const ScanContext& ctx) {
  const bool usable = port.bound() && port.online() && port.in().size() >= kWindowSize &&
                      port.out().size() >= kWindowSize;
  if (!usable) {
    go_offline();
    return;
  }
  const auto in = port.in();
  auto out = port.out();
  // The three status bytes R[5..7] read once, before this block's byte
  // stores (which may alias the image for the compiler): as R[4..7] in one
  // load where the byte order allows (usable: the window's 8 bytes are
  // there), shifted down past the echo R[4].
  static_assert(r::kStatus == 5 && r::kCommand == 6 && r::kWeighing == 7);
  std::uint32_t raw;
  if constexpr (std::endian::native == std::endian::little) {
    std::memcpy(&raw, in.data() + r::kReadValueSelected, 4);
    raw >>= 8;
  } else {
    raw = static_cast<std::uint32_t>(in[r::kStatus]) |
          static_cast<std::uint32_t>(in[r::kCommand]) << 8 |
          static_cast<std::uint32_t>(in[r::kWeighing]) << 16;
  }
  Online = true;
  StatusByte = static_cast<std::uint8_t>(raw);
  CommandByte = static_cast<std::uint8_t>(raw >> 8);
  WeighingByte = static_cast<std::uint8_t>(raw >> 16);
  // Decoded once per change of the three status bytes: status_ is a
  // function of them alone (raw: R[5] | R[6] << 8 | R[7] << 16), and
  // neither it nor status_raw_ is reflected (no debugger or HMI write), so
  // the last decode is still exact. Both start as the bytes 0, 0, 0 and
  // their decode.
  if (raw != status_raw_) {
    status_ = decode_status_changed(in);
    status_raw_ = raw;
  }

  if (!was_online_) {
    // Spec §7.2 start-up: full scale (clears Cal_Changed), format, model.
    want_fsd_ = want_format_ = want_model_ = true;
    was_online_ = true;
    out[w::kWriteValueSelect] = 0;
    out[w::kCommands] = 0;
  }
  if (status_.CalChanged && !prev_cal_changed_) want_fsd_ = want_format_ = true;
  if (status_.CmdError && !prev_cmd_error_) want_format_ = true;
  prev_cal_changed_ = status_.CalChanged;
  prev_cmd_error_ = status_.CmdError;

  // With nothing to read for itself and no read error or grant of its own,
  // run_own_reader() only sets Ready (= FormatReads > 0, want_fsd_ being
  // false): most scans, so no call.
  if (!want_fsd_ && !want_format_ && !want_model_ && holder_ != kOwnSlot &&
      !(rd_err_ & bit(kOwnSlot)))
    Ready = FormatReads > 0;
  else
    run_own_reader();
  arbitrate_read<SteadyRead>(ctx.now);
  // Idle with nothing pending, run_write() and run_command() do nothing
  // (next_in() of an empty mask is kNoSlot): most scans, so no call.
  if (wr_phase_ != WrPhase::Idle || wr_pending_ != 0) run_write(ctx.now);
  if (cmd_phase_ != CmdPhase::Idle || cmd_pending_ != 0) run_command(ctx.now);
  out[w::kOutputs] = outputs_;
}

template <bool SteadyRead>
inline void PR5510_Device::arbitrate_read(TIME now) {
  const auto in = port.in();
  // The steady read: the holder alone requests, the same code, echoed, no
  // read error anywhere. What the general path below does then: the holder
  // keeps the window (nobody to pass it on to, no urgent request to
  // preempt it), counts as served, and W[4] carries its code.
  // ReadPathsAgree (test_window_faults.cpp) compares it with the general
  // path over a random walk of requests, echoes, timeouts and faults.
  if (SteadyRead && holder_ != kNoSlot && rd_req_ == bit(holder_) && rd_err_ == 0 &&
      rd_code_[idx(holder_)] == holder_code_ && in[r::kReadValueSelected] == holder_code_) {
    holder_served_ = true;
    port.out()[w::kReadValueSelect] = holder_code_;
    ReadHolder = static_cast<SINT>(holder_);
    rd_req_ = 0;
    rd_urgent_ = 0;
    return;
  }
  const std::uint8_t waiting = static_cast<std::uint8_t>(rd_req_ & ~rd_err_);
  if (holder_ != kNoSlot) {
    const std::size_t h = idx(holder_);
    if (!(rd_req_ & bit(holder_))) {
      holder_ = kNoSlot;  // the holder let go (or was not called)
    } else if (rd_code_[h] != holder_code_) {
      holder_code_ = rd_code_[h];  // same holder, new code: wait for its echo again
      holder_served_ = false;
      grant_time_ = now;
    } else if (in[r::kReadValueSelected] == holder_code_) {
      // Served in an earlier scan: pass on if anybody else waits (an
      // urgent holder only to another urgent request).
      const std::uint8_t others = static_cast<std::uint8_t>(waiting & ~bit(holder_));
      const bool holder_urgent = (rd_urgent_ & bit(holder_)) != 0;
      if (holder_served_ && (holder_urgent ? (others & rd_urgent_) : others)) holder_ = kNoSlot;
      holder_served_ = true;
    } else if (now - grant_time_ > EchoTimeout) {
      read_error_[h] = error_id::kReadEchoTimeout;
      rd_err_ = static_cast<std::uint8_t>(rd_err_ | bit(holder_));
      holder_ = kNoSlot;
    }
  }
  if (holder_ != kNoSlot && !(rd_urgent_ & bit(holder_)) && (waiting & rd_urgent_)) {
    holder_ = kNoSlot;  // an urgent request preempts a normal holder
  }
  if (holder_ == kNoSlot) {
    const std::uint8_t urgent = static_cast<std::uint8_t>(waiting & rd_urgent_);
    const int s = next_in(urgent ? urgent : waiting, ReadHolder >= 0 ? ReadHolder + 1 : 0);
    if (s != kNoSlot) {
      holder_ = s;
      holder_code_ = rd_code_[idx(s)];
      holder_served_ = false;
      grant_time_ = now;
      ++ReadGrants;
    }
  }
  if (holder_ != kNoSlot) {
    port.out()[w::kReadValueSelect] = holder_code_;
    ReadHolder = static_cast<SINT>(holder_);
  } else {
    ReadHolder = -1;  // W[4] keeps its last code: harmless, and valid at once if asked again
  }
  // A slot that stopped requesting starts clean next time.
  if (const std::uint8_t stale = static_cast<std::uint8_t>(rd_err_ & ~rd_req_); stale) {
    for (int s = 0; s < kMaxClients; ++s)
      if (stale & bit(s)) read_error_[idx(s)] = error_id::kNone;
    rd_err_ = static_cast<std::uint8_t>(rd_err_ & rd_req_);
  }
  rd_req_ = 0;
  rd_urgent_ = 0;
}

}  // namespace plc::weighing

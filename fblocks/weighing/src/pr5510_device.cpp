#include "plc/fb/weighing/pr5510_device.hpp"

#include <bit>
#include <cstring>

namespace plc::weighing {

namespace {
constexpr std::uint8_t kFsd = static_cast<std::uint8_t>(ReadCode::FullScale);
constexpr std::uint8_t kFormat = static_cast<std::uint8_t>(ReadCode::Format);
constexpr std::uint8_t kModel = static_cast<std::uint8_t>(ReadCode::ModelVersion);
constexpr int kOwnSlot = 0;

// The status cache starts as the bytes 0, 0, 0 (status_raw_) and their decode.
static_assert(decode_status(std::array<std::uint8_t, kWindowSize>{}) == StatusBits{});

// decode_status() where the status bytes changed (a few scans in a
// hundred): out of line, so that operator() (every scan) needs fewer
// registers to save.
[[gnu::noinline]] StatusBits decode_status_changed(std::span<const std::uint8_t> in) {
  return decode_status(in);
}

// The status bit that shows a command took effect (spec §5.5 feedback
// column). Set Zero has no bit of its own that noise cannot flicker
// (Center Zero is +- 1/4 d), so it is judged by Cmd_Busy/Cmd_Error alone.
bool command_effect_seen(CommandBit b, const StatusBits& s) {
  switch (b) {
    case CommandBit::SetTare:
      return s.TareActive;
    case CommandBit::ResTare:
      return !s.TareActive;
    case CommandBit::SetTest:
      return s.TestActive;
    case CommandBit::ResTest:
      return !s.TestActive;
    case CommandBit::ResPower:
      return !s.PowerFail;
    case CommandBit::SetZero:
      break;
  }
  return true;
}
}  // namespace

int PR5510_Device::next_in(std::uint8_t mask, int from) {
  if (mask == 0) return kNoSlot;
  // Rotate so that `from` is bit 0, take the lowest set bit.
  const unsigned f = static_cast<unsigned>(from) % kMaxClients;
  const unsigned rot = ((mask >> f) | (mask << (kMaxClients - f))) & 0xFFU;
  return static_cast<int>((static_cast<unsigned>(__builtin_ctz(rot)) + f) % kMaxClients);
}

int PR5510_Device::attach() {
  if (clients_ >= kMaxClients) return kNoSlot;
  return clients_++;
}

bool PR5510_Device::request_write(int slot, std::uint8_t code, std::uint32_t raw) {
  if (!valid(slot)) return false;
  const std::size_t i = idx(slot);
  if (wr_status_[i] == WriteStatus::Pending || wr_status_[i] == WriteStatus::Active) return false;
  wr_status_[i] = WriteStatus::Pending;
  wr_pending_ = static_cast<std::uint8_t>(wr_pending_ | bit(slot));
  wr_error_[i] = error_id::kNone;
  wr_code_[i] = code;
  wr_raw_[i] = raw;
  return true;
}

void PR5510_Device::ack_write(int slot) {
  if (!valid(slot)) return;
  // An Active handshake runs to its end even if its block lets go of it.
  if (wr_status_[idx(slot)] != WriteStatus::Active) wr_status_[idx(slot)] = WriteStatus::Idle;
  wr_pending_ = static_cast<std::uint8_t>(wr_pending_ & ~bit(slot));
}

bool PR5510_Device::request_command(int slot, CommandBit command) {
  if (!valid(slot)) return false;
  const std::size_t i = idx(slot);
  if (cmd_status_[i] == CommandStatus::Pending || cmd_status_[i] == CommandStatus::Active)
    return false;
  cmd_status_[i] = CommandStatus::Pending;
  cmd_pending_ = static_cast<std::uint8_t>(cmd_pending_ | bit(slot));
  cmd_error_[i] = error_id::kNone;
  cmd_bit_[i] = command;
  return true;
}

void PR5510_Device::ack_command(int slot) {
  if (!valid(slot)) return;
  if (cmd_status_[idx(slot)] != CommandStatus::Active) cmd_status_[idx(slot)] = CommandStatus::Idle;
  cmd_pending_ = static_cast<std::uint8_t>(cmd_pending_ & ~bit(slot));
}

void PR5510_Device::go_offline() {
  Online = false;
  Ready = false;
  was_online_ = false;
  holder_ = kNoSlot;
  ReadHolder = -1;
  // Writes and commands cannot finish on a silent device: fail them, so no
  // block waits for ever. The window bytes restart clean when it returns.
  for (int s = 0; s < kMaxClients; ++s) {
    const std::size_t i = idx(s);
    if (wr_status_[i] == WriteStatus::Pending || wr_status_[i] == WriteStatus::Active) {
      wr_status_[i] = WriteStatus::Error;
      wr_error_[i] = error_id::kDeviceOffline;
    }
    if (cmd_status_[i] == CommandStatus::Pending || cmd_status_[i] == CommandStatus::Active) {
      cmd_status_[i] = CommandStatus::Error;
      cmd_error_[i] = error_id::kDeviceOffline;
    }
  }
  wr_phase_ = WrPhase::Idle;
  wr_slot_ = kNoSlot;
  cmd_phase_ = CmdPhase::Idle;
  cmd_slot_ = kNoSlot;
  rd_req_ = 0;
  rd_urgent_ = 0;
  wr_pending_ = 0;
  cmd_pending_ = 0;
}

template <bool SteadyRead>
void PR5510_Device::scan(const ScanContext& ctx) {
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

void PR5510_Device::run_own_reader() {
  const auto in = port.in();
  if (rd_err_ & bit(kOwnSlot)) {
    // No echo in time: the device's own reads simply try again.
    read_error_[idx(kOwnSlot)] = error_id::kNone;
    rd_err_ = static_cast<std::uint8_t>(rd_err_ & ~bit(kOwnSlot));
  }
  if (holder_ == kOwnSlot && in[r::kReadValueSelected] == holder_code_) {
    const std::uint32_t raw = read_raw();
    if (holder_code_ == kFsd && want_fsd_) {
      FullScale = static_cast<DINT>(raw);
      want_fsd_ = false;
    } else if (holder_code_ == kFormat && want_format_) {
      const FormatInfo f = unpack_format(raw, PackedWordOrder);
      Decimals = f.decimals;
      Unit = f.unit;
      Division = f.division;
      LastError = f.last_error;
      scale_ = 1.0f;
      for (unsigned d = 0; d < f.decimals && d < 9; ++d) scale_ *= 10.0f;
      ++FormatReads;
      want_format_ = false;
    } else if (holder_code_ == kModel && want_model_) {
      const ModelInfo m = unpack_model(raw, PackedWordOrder);
      Model = m.model;
      Version = m.version;
      want_model_ = false;
    }
  }
  Ready = !want_fsd_ && FormatReads > 0;
  if (want_fsd_) {
    request_read(kOwnSlot, kFsd);
  } else if (want_format_) {
    request_read(kOwnSlot, kFormat);
  } else if (want_model_) {
    request_read(kOwnSlot, kModel);
  }
}

template <bool SteadyRead>
void PR5510_Device::arbitrate_read(TIME now) {
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

void PR5510_Device::finish_write(std::uint16_t err) {
  wr_status_[idx(wr_slot_)] = err == error_id::kNone ? WriteStatus::Done : WriteStatus::Error;
  wr_error_[idx(wr_slot_)] = err;
  wr_slot_ = kNoSlot;
  wr_phase_ = WrPhase::Idle;
}

void PR5510_Device::run_write(TIME now) {
  auto out = port.out();
  const bool wa = status_.WriteActive;
  switch (wr_phase_) {
    case WrPhase::Idle: {
      const int s = next_in(wr_pending_, wr_next_);
      if (s == kNoSlot) break;
      wr_pending_ = static_cast<std::uint8_t>(wr_pending_ & ~bit(s));
      wr_slot_ = s;
      wr_next_ = (s + 1) % kMaxClients;
      wr_status_[idx(s)] = WriteStatus::Active;
      wr_phase_ = WrPhase::WaitFree;
      wr_since_ = now;
      [[fallthrough]];
    }
    case WrPhase::WaitFree:
      // Spec §3.6 step 1: wait for Write_Active = 0.
      if (!wa) {
        // Steps 2-3: the value, and the code in the same telegram when the
        // module is consistent.
        encode_raw(out, wr_raw_[idx(wr_slot_)], BusType);
        wr_since_ = now;
        if (ConsistentModule) {
          out[w::kWriteValueSelect] = wr_code_[idx(wr_slot_)];
          wr_phase_ = WrPhase::WaitAck;
        } else {
          wr_phase_ = WrPhase::PutCode;
        }
      } else if (now - wr_since_ > WriteTimeout) {
        finish_write(error_id::kWriteBusyTimeout);
      }
      break;
    case WrPhase::PutCode:
      if (now - wr_since_ >= std::chrono::milliseconds(kDeviceCycleMs)) {
        out[w::kWriteValueSelect] = wr_code_[idx(wr_slot_)];
        wr_phase_ = WrPhase::WaitAck;
        wr_since_ = now;
      }
      break;
    case WrPhase::WaitAck:
      // Step 4: Write_Active = 1 acknowledges; Cmd_Error tells failure.
      if (wa) {
        wr_cmd_error_ = status_.CmdError;
        out[w::kWriteValueSelect] = 0;  // step 5
        wr_phase_ = WrPhase::WaitRelease;
        wr_since_ = now;
      } else if (now - wr_since_ > WriteTimeout) {
        out[w::kWriteValueSelect] = 0;
        finish_write(error_id::kWriteAckTimeout);
      }
      break;
    case WrPhase::WaitRelease:
      // Step 6: Write_Active back to 0 before the next write.
      if (!wa) {
        if (wr_cmd_error_) {
          want_format_ = true;  // learn the device error number (code 4)
          wr_epoch_ = FormatReads;
          wr_phase_ = WrPhase::WaitErrorNo;
          wr_since_ = now;
        } else {
          finish_write(error_id::kNone);
        }
      } else if (now - wr_since_ > WriteTimeout) {
        finish_write(error_id::kWriteReleaseTimeout);
      }
      break;
    case WrPhase::WaitErrorNo:
      if (FormatReads > wr_epoch_) {
        finish_write(error_id::device_error(LastError));
      } else if (now - wr_since_ > EchoTimeout + EchoTimeout) {
        finish_write(error_id::kDeviceErrorUnknown);
      }
      break;
  }
}

void PR5510_Device::finish_command(std::uint16_t err) {
  cmd_status_[idx(cmd_slot_)] = err == error_id::kNone ? CommandStatus::Done : CommandStatus::Error;
  cmd_error_[idx(cmd_slot_)] = err;
  cmd_slot_ = kNoSlot;
}

void PR5510_Device::run_command(TIME now) {
  auto out = port.out();
  switch (cmd_phase_) {
    case CmdPhase::Idle: {
      const int s = next_in(cmd_pending_, cmd_next_);
      if (s == kNoSlot) break;
      cmd_pending_ = static_cast<std::uint8_t>(cmd_pending_ & ~bit(s));
      cmd_slot_ = s;
      cmd_next_ = (s + 1) % kMaxClients;
      cmd_status_[idx(s)] = CommandStatus::Active;
      // Spec §3.3: the function acts on the 0->1 edge of its flag.
      out[w::kCommands] = static_cast<std::uint8_t>(1U << static_cast<unsigned>(cmd_bit_[idx(s)]));
      cmd_phase_ = CmdPhase::High;
      cmd_since_ = now;
      break;
    }
    case CmdPhase::High:
      // Held at least 40 ms (CommandHold), then switched off again.
      if (now - cmd_since_ >= command_hold()) {
        out[w::kCommands] = 0;
        cmd_phase_ = CmdPhase::WaitDone;
        cmd_since_ = now;
      }
      break;
    case CmdPhase::WaitDone:
      // The device has sampled the edge by now; Cmd_Busy covers commands
      // that wait (tare waits for standstill, spec §7.1).
      if (!status_.CmdBusy) {
        if (!status_.CmdError && !command_effect_seen(cmd_bit_[idx(cmd_slot_)], status_)) {
          // Not busy, no error, but no result either (yet): the device may
          // not have sampled the edge, or ignores it. Wait, then give up.
          if (now - cmd_since_ > WriteTimeout) {
            finish_command(error_id::kCommandNoEffect);
            cmd_phase_ = CmdPhase::Gap;
          }
        } else if (status_.CmdError) {
          want_format_ = true;
          cmd_epoch_ = FormatReads;
          cmd_phase_ = CmdPhase::WaitErrorNo;
        } else {
          finish_command(error_id::kNone);
          cmd_phase_ = CmdPhase::Gap;
        }
      } else if (now - cmd_since_ > WriteTimeout) {
        finish_command(error_id::kCommandBusyTimeout);
        cmd_phase_ = CmdPhase::Gap;
      }
      break;
    case CmdPhase::WaitErrorNo:
      if (FormatReads > cmd_epoch_) {
        finish_command(error_id::device_error(LastError));
        cmd_phase_ = CmdPhase::Gap;
      } else if (now - cmd_since_ > WriteTimeout) {
        finish_command(error_id::kDeviceErrorUnknown);
        cmd_phase_ = CmdPhase::Gap;
      }
      break;
    case CmdPhase::Gap:
      // Low for CommandHold too, so the next edge is seen as an edge.
      if (now - cmd_since_ >= command_hold()) cmd_phase_ = CmdPhase::Idle;
      break;
  }
}

void PR5510_Device::operator()(const ScanContext& ctx) { scan<true>(ctx); }
void PR5510_Device::scan_general(const ScanContext& ctx) { scan<false>(ctx); }

}  // namespace plc::weighing

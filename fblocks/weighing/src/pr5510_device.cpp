#include "plc/fb/weighing/pr5510_device.hpp"

#include <bit>
#include <cstring>

namespace plc::weighing {

namespace {
constexpr std::uint8_t kFsd = static_cast<std::uint8_t>(ReadCode::FullScale);
constexpr std::uint8_t kFormat = static_cast<std::uint8_t>(ReadCode::Format);
constexpr std::uint8_t kModel = static_cast<std::uint8_t>(ReadCode::ModelVersion);

// The status cache starts as the bytes 0, 0, 0 (status_raw_) and their decode.
static_assert(decode_status(std::array<std::uint8_t, kWindowSize>{}) == StatusBits{});

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

// Out of line: see the header.
StatusBits PR5510_Device::decode_status_changed(std::span<const std::uint8_t> in) {
  return decode_status(in);
}

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

void PR5510_Device::scan_general(const ScanContext& ctx) { scan<false>(ctx); }

}  // namespace plc::weighing

// Fuzz target: PROFIdrive telegrams 3, 9 and 111 (fblocks/drive/telegrams.hpp,
// spec hiwin-e1-profinet.md Table 3.2.2) on both ends of the wire. The first
// byte picks the telegram and the part:
//  0 the decoders: decode -> encode is stable (a second round gives the same
//    bytes; reserved PZDs and bits are dropped the same way each time);
//  1 the simulated E1 takes any PLC telegram, scan after scan;
//  2 DriveAxis + SinaPos take any drive telegram, scan after scan, with any
//    block inputs.
#include <array>
#include <chrono>
#include <cstdint>

#include "fuzz_device.hpp"
#include "fuzz_input.hpp"
#include "hiwin_e1/hiwin_e1_model.hpp"
#include "plc/fb/drive/sina_pos.hpp"
#include "plc/fb/drive/telegrams.hpp"

using namespace plc;
using namespace plc::drive;
using plc::fuzz::FuzzInput;
using namespace std::chrono_literals;

namespace {

constexpr int kMaxScans = 2000;

template <class T>
void round_trip(FuzzInput& in) {
  std::array<std::uint8_t, T::kBytes> wire{}, once{}, twice{};
  in.fill(wire);
  T::decode(wire).encode(once);
  T::decode(once).encode(twice);
  if (once != twice) __builtin_trap();
}

void decoders(FuzzInput& in) {
  while (!in.empty()) {
    round_trip<Telegram3Out>(in);
    round_trip<Telegram3In>(in);
    round_trip<Telegram9Out>(in);
    round_trip<Telegram9In>(in);
    round_trip<Telegram111Out>(in);
    round_trip<Telegram111In>(in);
  }
}

void drive_model(FuzzInput& in, TelegramType type) {
  sim::HiwinE1Config cfg;
  cfg.telegram = type;
  sim::HiwinE1Model model(cfg);
  std::array<std::uint8_t, Telegram111Out::kBytes> from_plc{};
  std::array<std::uint8_t, Telegram111In::kBytes> to_plc{};
  const auto out = std::span(from_plc).first(out_bytes(type));
  const auto back = std::span(to_plc).first(in_bytes(type));
  TIME now{};
  for (int i = 0; i < kMaxScans && !in.empty(); ++i) {
    if (in.flag()) in.fill(out);  // else the PLC repeats its last telegram
    now += 1ms;
    model.step(now, 1ms, out, back);
  }
}

void axis_blocks(FuzzInput& in, TelegramType type) {
  DriveAxis axis;
  axis.Telegram = static_cast<UINT>(type);
  const auto dev = fuzz::fuzz_device(in, in_bytes(type), out_bytes(type));
  dev->bind(axis.Port);
  SinaPos pos;
  ScanContext ctx{TIME{}, 1ms, 0};
  for (int i = 0; i < kMaxScans && !in.empty(); ++i) {
    const std::uint8_t flags = in.byte();
    if (flags & 1) {  // new block inputs this scan
      const std::uint8_t b = in.byte();
      pos.EnableAxis = b & 1;
      pos.ExecuteMode = b & 2;
      pos.AckError = b & 4;
      pos.Positive = b & 8;
      pos.Negative = b & 16;
      pos.Jog1 = b & 32;
      pos.Jog2 = b & 64;
      pos.CancelTraversing = !(b & 128);
      pos.ModePos = in.integral<INT>();
      pos.Position = in.integral<DINT>();
      pos.Velocity = in.integral<DINT>();
      pos.OverV = in.integral<INT>();
      pos.OverAcc = in.integral<INT>();
      pos.OverDec = in.integral<INT>();
    }
    pos(ctx, axis);
    ctx.now += 1ms;
    ++ctx.cycle;
    dev->step(ctx.now, 1ms);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  const std::uint8_t sel = in.byte();
  static constexpr TelegramType kTypes[] = {TelegramType::Standard3, TelegramType::Standard9,
                                            TelegramType::Hiwin111};
  const TelegramType type = kTypes[sel % 3];
  switch ((sel / 3) % 3) {
    case 0:
      decoders(in);
      break;
    case 1:
      drive_model(in, type);
      break;
    default:
      axis_blocks(in, type);
      break;
  }
  return 0;
}

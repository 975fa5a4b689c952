// Fuzz target: the PR5510 fieldbus windows (fblocks/weighing/
// window_codec.hpp, spec sartorius-pr1721.md §3-§5) on both ends of the
// wire. The first byte picks the part:
//  0 the codec: status bits R[5..7] and the packed codes 4 and 5 decode and
//    encode back to the same bits, on both buses and both word orders;
//  1 the simulated PR5510 takes any write window, held for any number of
//    device cycles, with any configuration and front-panel keys between;
//  2 PR5510_Device with a read, a write, a command and a batch block takes
//    any read window, with any block inputs.
#include <array>
#include <chrono>
#include <cstdint>

#include "fuzz_device.hpp"
#include "fuzz_input.hpp"
#include "plc/fb/weighing/batch_weigh.hpp"
#include "plc/fb/weighing/command.hpp"
#include "plc/fb/weighing/read_value.hpp"
#include "plc/fb/weighing/write_value.hpp"
#include "pr5510/pr5510_model.hpp"

using namespace plc;
using namespace plc::weighing;
using plc::fuzz::FuzzInput;
using namespace std::chrono_literals;

namespace {

constexpr int kMaxScans = 3000;

void codec(FuzzInput& in) {
  while (!in.empty()) {
    std::array<std::uint8_t, kWindowSize> rd{}, back{};
    in.fill(rd);
    const Bus bus = in.flag() ? Bus::DeviceNet : Bus::Profibus;
    const PackedOrder order = in.flag() ? PackedOrder::CcLink : PackedOrder::MsbFirst;
    encode_status(decode_status(rd), back);
    for (std::size_t i = r::kStatus; i <= r::kWeighing; ++i)
      if (back[i] != rd[i]) __builtin_trap();  // all 24 status bits are defined (§3.4)
    const std::uint32_t raw = decode_raw(rd, bus);
    if (pack_format(unpack_format(raw, order), order) != raw ||
        pack_model(unpack_model(raw, order), order) != raw)
      __builtin_trap();
    encode_raw(back, raw, bus);
    if (decode_dint(back, bus) != decode_dint(rd, bus)) __builtin_trap();
    (void)decode_real(rd, bus);
  }
}

void device_model(FuzzInput& in) {
  sim::Pr5510Config cfg;
  const std::uint8_t c = in.byte();
  cfg.bus = (c & 1) ? Bus::DeviceNet : Bus::Profibus;
  cfg.packed_order = (c & 2) ? PackedOrder::CcLink : PackedOrder::MsbFirst;
  cfg.strict_codes = c & 4;
  cfg.legal_for_trade = c & 8;
  cfg.cal_switch_locked = c & 16;
  cfg.scale_interface = !(c & 32);
  sim::Pr5510Model model(cfg);
  std::array<std::uint8_t, kWindowSize> w{}, r{};
  TIME now{};
  for (int i = 0; i < kMaxScans && !in.empty(); ++i) {
    const std::uint8_t op = in.byte();
    switch (op & 7) {
      case 0:
        model.panel_start_calibration();
        break;
      case 1:
        model.panel_calibrate_zero();
        break;
      case 2:
        model.panel_calibrate_span(in.integral<std::int16_t>() / 100.0);
        break;
      case 3:
        model.panel_finish_calibration();
        break;
      case 4:
        model.power_cycle();
        break;
      default:
        if (op & 8) in.fill(w);
        // Hold the window for 1..16 ms (the device samples every 20 ms).
        for (int k = 0; k <= (op >> 4); ++k) {
          now += 1ms;
          model.step(now, 1ms, w, r);
        }
        break;
    }
  }
}

void blocks(FuzzInput& in) {
  PR5510_Device dev;
  const auto sim = fuzz::fuzz_device(in, kWindowSize, kWindowSize);
  sim->bind(dev.port);
  const std::uint8_t c = in.byte();
  dev.BusType = (c & 1) ? Bus::DeviceNet : Bus::Profibus;
  dev.PackedWordOrder = (c & 2) ? PackedOrder::CcLink : PackedOrder::MsbFirst;
  dev.ConsistentModule = c & 4;
  PR5510_ReadValue read;
  PR5510_WriteValue write;
  PR5510_Command command;
  PR5510_BatchWeigh batch;
  read.Device = write.Device = command.Device = batch.Device = &dev;
  batch.TargetWeight = 20;
  batch.FineSwitchPoint = 2;
  batch.TolPlus = batch.TolMinus = 0.1f;
  ScanContext ctx{TIME{}, 1ms, 0};
  for (int i = 0; i < kMaxScans && !in.empty(); ++i) {
    const std::uint8_t f = in.byte();
    read.Enable = f & 1;
    write.Execute = f & 2;
    command.Execute = f & 4;
    batch.Execute = f & 8;
    batch.Abort = f & 16;
    batch.Pause = f & 32;
    if (f & 64) {  // new block parameters
      read.Code = in.byte();
      write.Code = in.byte();
      write.Value = in.integral<DINT>();
      write.UseReal = in.flag();
      write.ValueReal = in.integral<REAL>();
      command.Command = static_cast<CommandBit>(in.byte() % kCommandBitCount);
    }
    if (f & 128) {  // new batch recipe, any numbers (NaN and infinities too)
      batch.TargetWeight = in.integral<REAL>();
      batch.FineSwitchPoint = in.integral<REAL>();
      batch.Preact = in.integral<REAL>();
      batch.TolPlus = in.integral<REAL>();
      batch.TolMinus = in.integral<REAL>();
      batch.MaxTopUps = in.integral<INT>();
    }
    ctx.now += 1ms;
    dev(ctx);
    read(ctx);
    write(ctx);
    command(ctx);
    batch(ctx);
    sim->step(ctx.now, 1ms);
    ++ctx.cycle;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  plc::fuzz::run_one_of(in, codec, device_model, blocks);
  return 0;
}

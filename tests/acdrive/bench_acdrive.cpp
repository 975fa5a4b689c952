// Cost per scan of the AC drive block and the simulated VF66B (issue 12):
//   acdrive_block_plus_model_step   AcDrive (running, 21 -> 71) + one vf66b
//                                   step through SimDevice
//   acdrive_block_only              AcDrive alone (the drive does not step)
//   acdrive_handwritten_21_71       the same work written by hand: decode
//                                   71, compose 21 (the reference for the
//                                   block's own cost)
//   acdrive_model_step_only         one vf66b step (SimDevice) alone
// After the Google Benchmark run, one `name: value unit` line per figure.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "plc/fb/acdrive/ac_drive.hpp"
#include "plc/io/sim_device.hpp"
#include "plc_bench/collector.hpp"
#include "vf66b/vf66b_model.hpp"

namespace {

using namespace plc;
using namespace plc::acdrive;
using namespace std::chrono_literals;

struct Cell {
  Cell() {
    sim::Vf66bConfig cfg;
    cfg.j09 = 1;
    cfg.j10 = 1;
    cfg.b10 = 3;
    cfg.b11 = 3;
    cfg.startup_time = 10ms;
    dev = std::make_unique<io::SimDevice>(std::make_unique<sim::Vf66bModel>(cfg));
    dev->bind(fb.Port);
    dev->step(ctx.now, 1ms);
    fb.Enable = true;
    for (int i = 0; i < 50; ++i) scan();
    fb.RunFwd = true;
    fb.SpeedRef = 900;
    for (int i = 0; i < 100; ++i) scan();
  }
  void tick() {
    ctx.now += 1ms;
    ++ctx.cycle;
    dev->step(ctx.now, 1ms);
  }
  void scan() {
    fb(ctx);
    tick();
  }
  ScanContext ctx{TIME{}, 1ms, 0};
  std::unique_ptr<io::SimDevice> dev;
  AcDrive fb;
};

void acdrive_block_plus_model_step(benchmark::State& st) {
  Cell c;
  for (auto _ : st) c.scan();
  if (c.fb.Error || !c.fb.Running) st.SkipWithError("the drive does not run");
  benchmark::DoNotOptimize(c.fb.ActualSpeed);
}
BENCHMARK(acdrive_block_plus_model_step);

void acdrive_block_only(benchmark::State& st) {
  Cell c;
  for (auto _ : st) {
    c.ctx.now += 1ms;
    c.fb(c.ctx);
    benchmark::DoNotOptimize(c.fb.Port.out()[0]);
  }
  if (c.fb.Error) st.SkipWithError("AcDrive reported an error");
}
BENCHMARK(acdrive_block_only);

// Decode 71, compose 21, as a program would without the block.
void acdrive_handwritten_21_71(benchmark::State& st) {
  Cell c;
  const auto in = c.fb.Port.in();
  const auto out = c.fb.Port.out();
  bool run = true;
  double ref = 900, actual = 0;
  bool faulted = false, running = false;
  for (auto _ : st) {
    benchmark::DoNotOptimize(run);
    benchmark::DoNotOptimize(ref);
    faulted = in[0] & 0x01;
    running = in[0] & 0x0C;
    actual = std::ldexp(static_cast<double>(static_cast<std::int16_t>(in[2] | (in[3] << 8))), -3);
    const auto bus = static_cast<std::int16_t>(std::nearbyint(std::ldexp(ref, 3)));
    out[0] = static_cast<std::uint8_t>((run && !faulted ? 0x01 : 0) | 0x60);
    out[1] = 0;
    out[2] = static_cast<std::uint8_t>(bus & 0xFF);
    out[3] = static_cast<std::uint8_t>((bus >> 8) & 0xFF);
    benchmark::DoNotOptimize(actual);
    benchmark::DoNotOptimize(running);
    benchmark::DoNotOptimize(out[0]);
  }
}
BENCHMARK(acdrive_handwritten_21_71);

void acdrive_model_step_only(benchmark::State& st) {
  Cell c;
  for (auto _ : st) c.tick();
  benchmark::DoNotOptimize(c.dev->inputs()[0]);
}
BENCHMARK(acdrive_model_step_only);

}  // namespace

int main(int argc, char** argv) {
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  c.print_wall_lines();
  return 0;
}

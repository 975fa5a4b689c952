// Cost per scan of the drive blocks and the simulated E1 (issue 3):
//   drive_pos_block_plus_model_step   SinaPos (travelling, telegram 111) +
//                                     one hiwin_e1 step through SimDevice
//   drive_pos_block_only              SinaPos + axis read/write, no drive step
//   drive_model_step_only             one hiwin_e1 step (SimDevice) alone
//   drive_mc_move_plus_model_step     MC_Power + MC_MoveRelative (re-triggered
//                                     moves) + one drive step
// After the Google Benchmark run, one `name: value unit` line per figure.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "hiwin_e1/hiwin_e1_model.hpp"
#include "plc/fb/drive/mc_blocks.hpp"
#include "plc/fb/drive/sina_pos.hpp"
#include "plc/io/sim_device.hpp"
#include "plc_bench/collector.hpp"

namespace {

using namespace plc;
using namespace plc::drive;
using namespace std::chrono_literals;

struct Cell {
  explicit Cell(sim::HiwinE1Config cfg = {}) {
    auto m = std::make_unique<sim::HiwinE1Model>(cfg);
    dev = std::make_unique<io::SimDevice>(std::move(m));
    dev->bind(axis.Port);
    dev->step(ctx.now, 1ms);
  }
  void tick() {
    ctx.now += 1ms;
    ++ctx.cycle;
    dev->step(ctx.now, 1ms);
  }
  ScanContext ctx{TIME{}, 1ms, 0};
  std::unique_ptr<io::SimDevice> dev;
  DriveAxis axis;
};

// A SinaPos in velocity mode (continuous travel), enabled and moving.
void setup_moving(Cell& c, SinaPos& fb) {
  fb.EnableAxis = true;
  for (int i = 0; i < 10; ++i) {
    fb(c.ctx, c.axis);
    c.tick();
  }
  fb.ModePos = 3;
  fb.Velocity = 600;
  fb.Positive = true;
  fb.ExecuteMode = true;
  for (int i = 0; i < 100; ++i) {
    fb(c.ctx, c.axis);
    c.tick();
  }
}

void drive_pos_block_plus_model_step(benchmark::State& st) {
  Cell c;
  SinaPos fb;
  setup_moving(c, fb);
  for (auto _ : st) {
    fb(c.ctx, c.axis);
    c.tick();
  }
  if (fb.Error) st.SkipWithError("SinaPos reported an error");
  benchmark::DoNotOptimize(fb.ActPosition);
}
BENCHMARK(drive_pos_block_plus_model_step);

void drive_pos_block_only(benchmark::State& st) {
  Cell c;
  SinaPos fb;
  setup_moving(c, fb);
  c.axis.SignOfLifeCheck = false;  // the drive does not step here
  for (auto _ : st) {
    c.ctx.now += 1ms;
    ++c.ctx.cycle;
    fb(c.ctx, c.axis);
  }
  benchmark::DoNotOptimize(fb.ActPosition);
}
BENCHMARK(drive_pos_block_only);

void drive_model_step_only(benchmark::State& st) {
  // Nobody counts the controller sign-of-life here: monitoring off so the
  // drive keeps travelling instead of tripping AL.FB1.
  sim::HiwinE1Config cfg;
  cfg.sign_of_life_monitoring = false;
  Cell c(cfg);
  SinaPos fb;
  setup_moving(c, fb);
  auto& model = static_cast<sim::HiwinE1Model&>(c.dev->model());
  for (auto _ : st) c.tick();
  if (model.state() != sim::HiwinE1Model::State::S4) st.SkipWithError("drive left S4");
  benchmark::DoNotOptimize(c.dev->inputs()[0]);
}
BENCHMARK(drive_model_step_only);

void drive_mc_move_plus_model_step(benchmark::State& st) {
  Cell c;
  MC_Power power;
  MC_MoveRelative move;
  power.Enable = true;
  move.Distance = 2000;
  move.Velocity = 200000;
  for (auto _ : st) {
    power(c.ctx, c.axis);
    move.Execute = power.Status && !move.Done;
    move(c.ctx, c.axis);
    c.tick();
  }
  if (power.Error || move.Error) st.SkipWithError("MC blocks reported an error");
}
BENCHMARK(drive_mc_move_plus_model_step);

}  // namespace

int main(int argc, char** argv) {
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  c.print_wall_lines();
  return 0;
}

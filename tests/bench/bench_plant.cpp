// Plant models and control blocks (issue 25): the cost of one plant sample
// per state dimension (1..20 states, one input with dead time, one output),
// one PID_Compact and one CONT_C call per scan, and the oven cell's
// virtual-time speed with the plant in the loop (programs/oven: a 100 ms
// task, the plant sampled every 100 ms) and with the plant sampled every
// 1 ms under the same task (100 plant samples per scan).
//
// Prints one `name: value unit` line per figure on stdout. Environment:
//   PLC_SOURCE_DIR  repository root (default: the one it was built from)
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "plc/cell_config.hpp"
#include "plc/fb/control/cont_c.hpp"
#include "plc/fb/control/pid_compact.hpp"
#include "plc/runtime.hpp"
#include "plc/sim/plant/linear_plant.hpp"
#include "plc_bench/collector.hpp"

namespace {

using namespace std::chrono_literals;
namespace pl = plc::plant;

std::string source_dir() {
  const char* s = std::getenv("PLC_SOURCE_DIR");
  return s ? s : PLC_DEFAULT_SOURCE_DIR;
}

// A chain of n first-order lags (time constants 1 .. n s, coupled
// forwards), one input with 25 ms dead time, the last state as output: a
// dense enough Phi (lower triangular after discretisation) for the n^2
// product to be what it costs.
pl::LinearPlant chain(int n) {
  pl::Rows a(n, std::vector<double>(n, 0.0)), b(n, std::vector<double>(1, 0.0)),
      c(1, std::vector<double>(n, 0.0));
  for (int i = 0; i < n; ++i) {
    a[i][i] = -1.0 / (1.0 + i);
    if (i) a[i][i - 1] = 1.0 / (1.0 + i);
  }
  b[0][0] = 1.0;
  c[0][n - 1] = 1.0;
  pl::DiscretiseOptions opt;
  opt.dead_time = {25ms};
  return pl::LinearPlant(pl::discretise_zoh(pl::state_space(a, b, c, {}), 1ms, opt));
}

void BM_PlantStep(benchmark::State& state) {
  pl::LinearPlant p = chain(static_cast<int>(state.range(0)));
  double u[1] = {1.0};
  double sum = 0;
  for (auto _ : state) {
    p.step(u);
    sum += p.outputs()[0];
    u[0] = sum > 1e300 ? 0.0 : 1.0;  // keeps the loop honest, never true
  }
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_PlantStep)->DenseRange(1, 20, 1);

// One scan of a PI(D) loop: PID_Compact with D filter and PWM, fed a
// slowly moving measurement.
void BM_PidCompactCall(benchmark::State& state) {
  plc::control::PID_Compact pid;
  pid.Gain = 3.0f;
  pid.Ti = 40.0f;
  pid.Td = 5.0f;
  pid.Setpoint = 60.0f;
  plc::ScanContext ctx{};
  ctx.period = 10ms;
  float x = 20.0f;
  for (auto _ : state) {
    pid.Input = x;
    pid(ctx);
    x += (pid.Output * 0.01f - (x - 20.0f) * 0.001f) * 0.01f;
    ctx.now += 10ms;
  }
  benchmark::DoNotOptimize(pid.Output);
}
BENCHMARK(BM_PidCompactCall);

void BM_ContCCall(benchmark::State& state) {
  plc::control::CONT_C c;
  c.MAN_ON = false;
  c.D_SEL = true;
  c.CYCLE = 10ms;
  c.SP_INT = 60.0f;
  plc::ScanContext ctx{};
  ctx.period = 10ms;
  float x = 20.0f;
  for (auto _ : state) {
    c.PV_IN = x;
    c(ctx);
    x += (c.LMN * 0.01f - (x - 20.0f) * 0.001f) * 0.01f;
    ctx.now += 10ms;
  }
  benchmark::DoNotOptimize(c.LMN);
}
BENCHMARK(BM_ContCCall);

double g_oven_speed = 0, g_oven_tick_us = 0, g_fine_speed = 0, g_fine_tick_us = 0;

// The oven cell as configured, or with the plant sampled every 1 ms.
void oven_run(benchmark::State& state, bool fine, double& speed, double& tick_us) {
  plc::CellConfig cfg = plc::load_cell_config(source_dir() + "/programs/oven/cell.yaml");
  if (fine) cfg.devices[0].params.values.set("sample", "1ms");
  plc::Runtime rt(cfg);
  rt.start(plc::io::ClockMode::Virtual);
  std::uint64_t ticks = 0;
  const auto w0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    rt.tick();
    ++ticks;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  rt.finish();
  speed = std::chrono::duration<double>(rt.now()).count() / wall;
  tick_us = wall / double(ticks) * 1e6;
}

void BM_OvenCellVirtualTick(benchmark::State& state) {
  oven_run(state, false, g_oven_speed, g_oven_tick_us);
}
BENCHMARK(BM_OvenCellVirtualTick)->MinTime(2.0);

void BM_OvenCellFinePlantVirtualTick(benchmark::State& state) {
  oven_run(state, true, g_fine_speed, g_fine_tick_us);
}
BENCHMARK(BM_OvenCellFinePlantVirtualTick)->MinTime(2.0);

}  // namespace

int main(int argc, char** argv) {
  try {
    plc::load_cell_config(source_dir() + "/programs/oven/cell.yaml");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_plant: %s (set PLC_SOURCE_DIR to the repository root)\n", e.what());
    return 2;
  }
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  for (int n = 1; n <= 20; ++n) {
    const double ns = c.cpu("BM_PlantStep/" + std::to_string(n));
    if (ns > 0) std::printf("plant_step_%d_states: %.1f ns\n", n, ns);
  }
  if (const double ns = c.cpu("BM_PidCompactCall"); ns > 0)
    std::printf("pid_compact_call: %.1f ns\n", ns);
  if (const double ns = c.cpu("BM_ContCCall"); ns > 0) std::printf("cont_c_call: %.1f ns\n", ns);
  if (g_oven_speed > 0) {
    std::printf("oven_virtual_tick: %.3f us\n", g_oven_tick_us);
    std::printf("oven_virtual_speed: %.0f x real time\n", g_oven_speed);
  }
  if (g_fine_speed > 0) {
    std::printf("oven_fine_plant_virtual_tick: %.3f us\n", g_fine_tick_us);
    std::printf("oven_fine_plant_virtual_speed: %.0f x real time\n", g_fine_speed);
  }
  return 0;
}

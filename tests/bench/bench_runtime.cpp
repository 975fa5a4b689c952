// Runtime benchmarks (issue 2): virtual-time scans per second of the demo
// cell and of the filling cell (three device models), real-time wake
// latency of a 1 ms task (with cyclictest from rt-tests in the same run for
// comparison, when it is installed), and the cost of a scan's statistics
// (issue 10).
//
// Prints one `name: value unit` line per figure on stdout. Environment:
//   PLC_BENCH_RT_SECONDS  length of the real-time run (default 10; 0 = no
//                         real-time run: scripts/bench runs it separately)
//   PLC_SOURCE_DIR        repository root (default: the one it was built from)
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "plc/cell_config.hpp"
#include "plc/runtime.hpp"
#include "plc_bench/collector.hpp"

namespace {

using namespace std::chrono_literals;

std::string source_dir() {
  const char* s = std::getenv("PLC_SOURCE_DIR");
  return s ? s : PLC_DEFAULT_SOURCE_DIR;  // the checkout this was built from
}

double g_scans_per_s = 0, g_speed = 0, g_us_per_tick = 0;
double g_fill_us_per_scan = 0, g_fill_speed = 0;

// One benchmark iteration = one base tick of the demo cell (1 ms of virtual
// time: device step + the fast task, and the slow task every 10th tick).
void BM_DemoVirtualTick(benchmark::State& state) {
  const plc::CellConfig cfg = plc::load_cell_config(source_dir() + "/programs/demo/cell.yaml");
  plc::Runtime rt(cfg);
  rt.start(plc::io::ClockMode::Virtual);
  std::uint64_t ticks = 0;
  const auto w0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    rt.tick();
    ++ticks;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  std::uint64_t scans = 0;
  for (const auto& t : rt.tasks()) scans += t->stats.scans();
  rt.finish();
  g_scans_per_s = double(scans) / wall;
  g_speed = std::chrono::duration<double>(rt.now()).count() / wall;
  g_us_per_tick = wall / double(ticks) * 1e6;
  state.counters["scans_per_s"] = g_scans_per_s;
}
BENCHMARK(BM_DemoVirtualTick)->MinTime(2.0);

// One iteration = one base tick (1 ms) of the filling cell: the three device
// models (E1 servo, PR5510, NORD F-device) step, then its one 1 ms task.
void BM_FillingCellVirtualTick(benchmark::State& state) {
  const plc::CellConfig cfg =
      plc::load_cell_config(source_dir() + "/programs/filling_cell/cell.yaml");
  plc::Runtime rt(cfg);
  rt.start(plc::io::ClockMode::Virtual);
  const auto w0 = std::chrono::steady_clock::now();
  for (auto _ : state) rt.tick();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  const std::uint64_t scans = rt.tasks()[0]->stats.scans();
  rt.finish();
  g_fill_us_per_scan = wall / double(scans) * 1e6;
  g_fill_speed = std::chrono::duration<double>(rt.now()).count() / wall;
}
BENCHMARK(BM_FillingCellVirtualTick)->MinTime(2.0);

// What the scan thread pays per scan for its statistics (wake latency and
// scan time into their histograms, the scan count): into the live,
// snapshot-able LiveTaskStats, and, for comparison, into plain fields that
// no other thread may read (as before issue 10).

void BM_TaskStatsLive(benchmark::State& state) {
  plc::LiveTaskStats s;
  std::int64_t v = 0;
  for (auto _ : state) {
    v = (v * 1103515245 + 12345) & 0xFFFFF;  // 0 .. 1 ms, spread over the buckets
    s.record_latency(v >> 4);
    s.record_scan(v);
  }
  benchmark::DoNotOptimize(s.scans());
}
BENCHMARK(BM_TaskStatsLive)->MinTime(0.5);

void BM_TaskStatsPlain(benchmark::State& state) {
  plc::Histogram scan, latency;
  std::uint64_t scans = 0;
  std::int64_t v = 0;
  for (auto _ : state) {
    v = (v * 1103515245 + 12345) & 0xFFFFF;
    latency.record(v >> 4);
    scan.record(v);
    ++scans;
    benchmark::ClobberMemory();
  }
  benchmark::DoNotOptimize(scans);
  benchmark::DoNotOptimize(scan.count() + latency.count());
}
BENCHMARK(BM_TaskStatsPlain)->MinTime(0.5);

void realtime_latency() {
  const char* env = std::getenv("PLC_BENCH_RT_SECONDS");
  const int seconds = env ? std::atoi(env) : 10;
  if (seconds <= 0) return;
  plc::CellConfig cfg = plc::parse_cell_config(R"(
cell: latency
tasks: [{name: t1ms, period: 1ms, priority: 0, programs: [Tank]}]
programs: [{name: Tank, type: TankCycle}]
plugins: [{name: sim}]
devices: [{name: tank1, plugin: sim, model: first_order, input: "%IB0", output: "%QB0"}]
)",
                                               "latency.yaml");
  plc::Runtime rt(cfg);
  rt.run(plc::io::ClockMode::RealTime, std::chrono::seconds(seconds));
  const plc::TaskStats s = rt.tasks()[0]->stats.snapshot();
  std::printf("rt_1ms_wake_latency_p50: %.1f us\n", double(s.latency_ns.percentile(0.50)) / 1000);
  std::printf("rt_1ms_wake_latency_p99: %.1f us\n", double(s.latency_ns.percentile(0.99)) / 1000);
  std::printf("rt_1ms_wake_latency_p999: %.1f us\n", double(s.latency_ns.percentile(0.999)) / 1000);
  std::printf("rt_1ms_wake_latency_max: %.1f us\n", double(s.latency_ns.max()) / 1000);
  std::printf("rt_1ms_scans: %llu scans\n", static_cast<unsigned long long>(s.scans));
  std::printf("rt_1ms_overruns: %llu scans\n", static_cast<unsigned long long>(s.overruns));
  std::fflush(stdout);

  // cyclictest on the same machine, same interval and priority, same length.
  const std::string cmd =
      "cyclictest -q -m -t1 -p49 -i1000 -l" + std::to_string(seconds * 1000) + " 2>/dev/null";
  if (std::FILE* f = ::popen(cmd.c_str(), "r")) {
    char line[512];
    long mn = -1, avg = -1, mx = -1;
    while (std::fgets(line, sizeof line, f)) {
      const char* p = std::strstr(line, "Min:");
      if (p) std::sscanf(p, "Min: %ld Act: %*s Avg: %ld Max: %ld", &mn, &avg, &mx);
    }
    ::pclose(f);
    if (mn >= 0) {
      std::printf("cyclictest_1ms_min: %ld us\n", mn);
      std::printf("cyclictest_1ms_avg: %ld us\n", avg);
      std::printf("cyclictest_1ms_max: %ld us\n", mx);
    } else {
      std::printf("cyclictest_1ms: unavailable (install rt-tests)\n");
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    plc::load_cell_config(source_dir() + "/programs/demo/cell.yaml");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_runtime: %s (set PLC_SOURCE_DIR to the repository root)\n",
                 e.what());
    return 2;
  }
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  const double stats_live_ns = c.cpu("BM_TaskStatsLive");
  const double stats_plain_ns = c.cpu("BM_TaskStatsPlain");
  std::printf("task_stats_per_scan_live: %.2f ns\n", stats_live_ns);
  std::printf("task_stats_per_scan_plain: %.2f ns\n", stats_plain_ns);
  if (g_scans_per_s > 0) {  // (not filtered out with --benchmark_filter)
    std::printf("demo_virtual_scans_per_s: %.0f scans/s\n", g_scans_per_s);
    std::printf("demo_virtual_tick: %.3f us\n", g_us_per_tick);
    std::printf("demo_virtual_speed: %.0f x real time\n", g_speed);
  }
  if (g_fill_us_per_scan > 0) {
    std::printf("filling_virtual_scan: %.3f us\n", g_fill_us_per_scan);
    std::printf("filling_virtual_speed: %.0f x real time\n", g_fill_speed);
  }
  realtime_latency();
  return 0;
}

// Online change of a 1,000-FB program (tests/bench/big_program.cpp, 6,001
// reflected fields), virtual time, period 1 ms:
//   online_change_prepare     load the new build, construct, compare (console
//                             thread, outside any scan)
//   online_change_scan        one ordinary scan of the program
//   online_change_switch_scan the scan that switches (copies every field's
//                             value, then runs the new code)
//   online_change_switch_copy the copy alone (the rest of switch_scan is the
//                             new code's first, cache-cold scan)
//   online_change_jitter      switch_scan - scan: what the switch adds to the
//                             task's scan (target: at most one period)
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>

#include "plc/cell_config.hpp"
#include "plc/online_change.hpp"
#include "plc/runtime.hpp"
#include "plc_bench/collector.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const fs::path& folder() {
  static const fs::path d = [] {
    auto p = fs::temp_directory_path() / ("softplc-bench-online-" + std::to_string(getpid()));
    fs::create_directories(p);
    return p;
  }();
  return d;
}

void install(const char* built) {
  fs::copy_file(built, folder() / "libbig.so", fs::copy_options::overwrite_existing);
}

std::unique_ptr<plc::Runtime> big_cell() {
  const char* yaml = R"(
libraries: [libbig.so]
tasks:
  - name: main
    period: 1ms
    programs: [Big]
programs:
  - name: Big
    type: Big
)";
  install(BENCH_BIG_V1);
  auto rt = std::make_unique<plc::Runtime>(
      plc::parse_cell_config(yaml, (folder() / "cell.yaml").string()));
  rt->start(plc::io::ClockMode::Virtual);
  for (int i = 0; i < 100; ++i) rt->step_scan();  // timers running, counters counting
  return rt;
}

// A cell with the version-2 build prepared and committed: the next scan of
// its task switches.
struct Committed {
  std::unique_ptr<plc::Runtime> rt = big_cell();
  std::unique_ptr<plc::OnlineChange> change;
  explicit Committed(benchmark::State& state) {
    install(BENCH_BIG_V2);
    change = std::make_unique<plc::OnlineChange>(*rt);
    const auto report = change->prepare("");
    if (!report.refused.empty()) state.SkipWithError(report.refused.c_str());
    change->commit();
  }
};

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

void BM_Scan(benchmark::State& state) {
  auto rt = big_cell();
  for (auto _ : state) {
    const auto t0 = Clock::now();
    rt->step_scan();
    state.SetIterationTime(seconds(Clock::now() - t0));
  }
}
BENCHMARK(BM_Scan)->UseManualTime()->Iterations(2000);

void BM_Prepare(benchmark::State& state) {
  auto rt = big_cell();
  install(BENCH_BIG_V2);
  for (auto _ : state) {
    const auto t0 = Clock::now();
    plc::OnlineChange change(*rt);
    const auto report = change.prepare("");
    state.SetIterationTime(seconds(Clock::now() - t0));
    if (!report.refused.empty()) state.SkipWithError(report.refused.c_str());
  }
}
BENCHMARK(BM_Prepare)->UseManualTime()->Iterations(30);

void BM_SwitchScan(benchmark::State& state) {
  for (auto _ : state) {
    Committed c(state);
    const auto t0 = Clock::now();
    c.rt->step_scan();  // applies the swap at its start
    state.SetIterationTime(seconds(Clock::now() - t0));
    if (!c.change->switched()) state.SkipWithError("did not switch");
    c.change->finish();
  }
}
BENCHMARK(BM_SwitchScan)->UseManualTime()->Iterations(30);

// The copy alone (what the task's thread does at the boundary before the
// first scan of the new code).
void BM_SwitchCopy(benchmark::State& state) {
  for (auto _ : state) {
    Committed c(state);
    plc::TaskRuntime& t = *c.rt->tasks()[0];
    const auto t0 = Clock::now();
    plc::apply_program_swap(t, *t.swap.load());
    state.SetIterationTime(seconds(Clock::now() - t0));
    c.change->finish();
  }
}
BENCHMARK(BM_SwitchCopy)->UseManualTime()->Iterations(30);

}  // namespace

int main(int argc, char** argv) {
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  auto get = [&](const char* prefix) { return c.wall(prefix); };
  const double scan = get("BM_Scan"), sw = get("BM_SwitchScan"), prep = get("BM_Prepare");
  std::printf("online_change_prepare: %.0f us\n", prep / 1e3);
  std::printf("online_change_scan: %.1f us\n", scan / 1e3);
  std::printf("online_change_switch_scan: %.1f us\n", sw / 1e3);
  std::printf("online_change_switch_copy: %.1f us\n", get("BM_SwitchCopy") / 1e3);
  std::printf("online_change_jitter: %.1f us\n", (sw - scan) / 1e3);
  std::printf("online_change_jitter_in_periods: %.3f periods of 1 ms\n", (sw - scan) / 1e6);
  std::error_code ec;
  fs::remove_all(folder(), ec);
  return 0;
}

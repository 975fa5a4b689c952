// Debugger costs per scan (issue 6): 10 active conditional breakpoints, and
// tracing 100 variables (CSV and VCD), against the same cell without a
// debugger, in one run. Costs are CPU time of the scan thread (the trace's
// formatting runs on a writer thread; its throughput is the *_wall figure).
// Prints `name: value unit` lines.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <string>
#include <thread>

#include "plc/debug/debugger.hpp"
#include "plc/program.hpp"
#include "plc_bench/collector.hpp"

namespace {

using namespace plc;

// 100 variables that change every scan (a fixed-seed xorshift).
class HundredVars : public ProgramBase<HundredVars> {
 public:
  std::array<DINT, 50> i{};
  std::array<REAL, 25> r{};
  std::array<BOOL, 25> b{};
  std::uint32_t x = 2463534242u;
  void cycle(const ScanContext&) override {
    for (auto& v : i) v = DINT(next() % 100000);
    for (auto& v : r) v = REAL(next() % 1000) * 0.5F;
    for (auto& v : b) v = (next() & 1U) != 0;
  }
  std::uint32_t next() {
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return x;
  }
  PLC_REFLECT(i, r, b)
};
PLC_REGISTER_PROGRAM(HundredVars)

const char* kCell = R"(
tasks: [{name: main, period: 1ms, watchdog: 0, programs: [P]}]
programs: [{name: P, type: HundredVars}]
)";

std::unique_ptr<debug::Debugger> make_debugger() {
  static CellConfig cfg = parse_cell_config(kCell, "bench.yaml");
  return std::make_unique<debug::Debugger>([] { return std::make_unique<Runtime>(cfg); },
                                           debug::Debugger::Options{});
}

void BM_ScanNoDebugger(benchmark::State& state) {
  Runtime rt(parse_cell_config(kCell, "bench.yaml"));
  rt.start(io::ClockMode::Virtual);
  for (auto _ : state) rt.step_scan();
  rt.finish();
}
BENCHMARK(BM_ScanNoDebugger)->MinTime(1.0);

// `paced`: every kPaceScans scans the timer stops while the writer thread
// catches up. kPaceScans is one trace block (Trace::kBlockRows), so the
// block handed off at the 256th row is formatted during the pause, as in
// real time, where a 1 ms period leaves the writer idle most of the time
// and its work rarely overlaps a scan. Unpaced, back to back scans outrun
// the writer's formatting (the *_wall figure): the scan thread's CPU time
// then includes its waits for free blocks, and the writer, busy on the
// other core the whole time, competes with it for the memory and caches
// the two cores share. Paced costs are taken against the idle debugger
// paced the same way, so the pauses (caches refilled after each sleep)
// are in both figures.
constexpr int kPaceScans = 256;
void pace(benchmark::State& state, int& n) {
  if (++n < kPaceScans) return;
  state.PauseTiming();
  // The writer formats a row in about 8 us: 256 rows in about 2 ms.
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  n = 0;
  state.ResumeTiming();
}

void BM_ScanDebuggerIdle(benchmark::State& state) {
  auto d = make_debugger();
  for (auto _ : state) d->runtime().step_scan();
}
BENCHMARK(BM_ScanDebuggerIdle)->MinTime(1.0);

void BM_ScanDebuggerIdlePaced(benchmark::State& state) {
  auto d = make_debugger();
  int n = 0;
  for (auto _ : state) {
    d->runtime().step_scan();
    pace(state, n);
  }
}
BENCHMARK(BM_ScanDebuggerIdlePaced)->MinTime(1.0);

void BM_TenBreakpoints(benchmark::State& state) {
  auto d = make_debugger();
  for (int k = 0; k < 10; ++k)  // never true: they are evaluated every scan
    d->execute("break P.i[" + std::to_string(k) + "] > 2000000 AND P.r[" + std::to_string(k) +
               "] < -1.0");
  for (auto _ : state) d->runtime().step_scan();
}
BENCHMARK(BM_TenBreakpoints)->MinTime(1.0);

// The debugger command that adds the program's 100 variables to the trace.
std::string trace_add_all() {
  std::string add = "trace add";
  for (int k = 0; k < 50; ++k) add += " P.i[" + std::to_string(k) + "]";
  for (int k = 0; k < 25; ++k) add += " P.r[" + std::to_string(k) + "]";
  for (int k = 0; k < 25; ++k) add += " P.b[" + std::to_string(k) + "]";
  return add;
}

void trace_bench(benchmark::State& state, const char* file, bool paced = false) {
  auto d = make_debugger();
  d->execute(trace_add_all());
  d->execute(std::string("trace start ") + file);
  int n = 0;
  for (auto _ : state) {
    d->runtime().step_scan();
    if (paced) pace(state, n);
  }
  d->execute("trace stop");
  std::remove(file);
}
void BM_Trace100Csv(benchmark::State& state) { trace_bench(state, "/tmp/plc_bench_trace.csv"); }
void BM_Trace100Vcd(benchmark::State& state) { trace_bench(state, "/tmp/plc_bench_trace.vcd"); }
void BM_Trace100CsvPaced(benchmark::State& state) {
  trace_bench(state, "/tmp/plc_bench_trace_paced.csv", true);
}
BENCHMARK(BM_Trace100Csv)->MinTime(1.0);
BENCHMARK(BM_Trace100CsvPaced)->MinTime(1.0);
BENCHMARK(BM_Trace100Vcd)->MinTime(1.0);

// Recording every scan (issue 10): the scan thread's share (the file is
// written by the writer thread). The cell's image is the default size
// (1 KB %Q, 4 KB %M), which the per-scan output hash covers.
void record_bench(benchmark::State& state, bool paced) {
  auto d = make_debugger();
  const char* file = "/tmp/plc_bench_record.rec";
  d->execute(std::string("record ") + file);
  int n = 0;
  for (auto _ : state) {
    d->runtime().step_scan();
    if (paced) pace(state, n);  // 256 scans of records: the writer writes a block meanwhile
  }
  d->execute("record stop");
  std::remove(file);
}
void BM_Record(benchmark::State& state) { record_bench(state, false); }
void BM_RecordPaced(benchmark::State& state) { record_bench(state, true); }
BENCHMARK(BM_Record)->MinTime(1.0);
BENCHMARK(BM_RecordPaced)->MinTime(1.0);

// `bench_debugger --count-scans MODE N`: N scans of the bench's cell with
// the debugger idle, tracing the 100 variables or recording (MODE idle,
// trace or record), and nothing else, so that callgrind counts what the
// timed benchmarks above time (scripts/cell_instructions.py:
// bench_cell_scan_costs takes two N apart, as for the example cells).
int count_scans(const std::string& mode, long n) {
  auto d = make_debugger();
  const std::string file = "/tmp/plc_bench_count_" + mode + "_" + std::to_string(::getpid());
  if (mode == "trace") {
    d->execute(trace_add_all());
    d->execute("trace start " + file + ".csv");
  } else if (mode == "record") {
    d->execute("record " + file + ".rec");
  } else if (mode != "idle") {
    std::fprintf(stderr, "bench_debugger: --count-scans: MODE is idle, trace or record\n");
    return 2;
  }
  for (long k = 0; k < n; ++k) d->runtime().step_scan();
  if (mode == "trace") d->execute("trace stop");
  if (mode == "record") d->execute("record stop");
  std::remove((file + ".csv").c_str());
  std::remove((file + ".rec").c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "--count-scans") {
    char* end = nullptr;
    const long n = std::strtol(argv[3], &end, 10);
    if (*end != '\0' || n < 0) {
      std::fprintf(stderr, "bench_debugger: --count-scans MODE N: N is a number of scans\n");
      return 2;
    }
    return count_scans(argv[2], n);
  }
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  auto get = [&](const char* prefix) { return c.cpu(prefix); };
  const double base = get("BM_ScanNoDebugger");
  const double idle = get("BM_ScanDebuggerIdle");
  const double bp = get("BM_TenBreakpoints");
  const double csv = get("BM_Trace100Csv");
  const double vcd = get("BM_Trace100Vcd");
  std::printf("scan_100_vars_no_debugger: %.0f ns\n", base);
  std::printf("debugger_idle_overhead: %.0f ns/scan\n", idle - base);
  std::printf("breakpoints_10_cost: %.0f ns/scan\n", bp - idle);
  std::printf("breakpoint_cost_each: %.1f ns/scan\n", (bp - idle) / 10);
  std::printf("trace_100_vars_csv_cost: %.0f ns/scan\n", csv - idle);
  std::printf("trace_100_vars_vcd_cost: %.0f ns/scan\n", vcd - idle);
  const double idle_paced = get("BM_ScanDebuggerIdlePaced");
  std::printf("trace_100_vars_csv_paced_cost: %.0f ns/scan\n",
              get("BM_Trace100CsvPaced") - idle_paced);
  std::printf("record_cost: %.0f ns/scan\n", get("BM_Record") - idle);
  std::printf("record_paced_cost: %.0f ns/scan\n", get("BM_RecordPaced") - idle_paced);
  // Wall time per scan with the trace: in virtual time the scan waits for
  // the writer thread when it falls behind (backpressure), so this is the
  // formatting throughput, paid on the other core.
  std::printf("trace_100_vars_csv_wall: %.0f ns/scan\n", c.wall("BM_Trace100Csv"));
  std::printf("trace_100_vars_vcd_wall: %.0f ns/scan\n", c.wall("BM_Trace100Vcd"));
  return 0;
}

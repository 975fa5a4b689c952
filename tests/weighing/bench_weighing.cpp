// Cost per scan of the weighing blocks. Prints one `name: value unit` line
// per figure:
//   batch_block_plus_window_per_scan  PR5510_Device + PR5510_BatchWeigh, one scan
//   read_value_plus_window_per_scan   PR5510_Device + one PR5510_ReadValue
//   pr5510_model_step_per_ms          the simulated PR5510 + filling process, 1 ms
//   closed_loop_scan_per_ms           blocks + SimDevice step (a virtual-time scan)
//   virtual_time_speedup              1 ms / closed_loop_scan_per_ms
// The block figures replay window bytes recorded from a closed-loop run of
// three batches (so the model's cost is not in them); a checksum of the
// block outputs proves that the replay takes the same path as the record.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "plc/fb/weighing/batch_weigh.hpp"
#include "plc/fb/weighing/read_value.hpp"
#include "pr5510_cell.hpp"

namespace wg = plc::weighing;
using namespace std::chrono_literals;

namespace {

struct Recording {
  wg::PR5510_Device dev_at_start;
  wg::PR5510_BatchWeigh batch_at_start;
  std::vector<std::array<std::uint8_t, 8>> inputs;  // R window per scan
  std::vector<bool> execute;
  std::uint64_t checksum = 0;
  plc::TIME t0{};
};

void setup(wg::PR5510_BatchWeigh& b, wg::PR5510_Device& dev) {
  b.Device = &dev;
  b.TargetWeight = 20.0f;
  b.FineSwitchPoint = 3.0f;
  b.Preact = 0.15f;
  b.TolPlus = b.TolMinus = 0.03f;
  b.EmptyWeight = 0.05f;
}

std::uint64_t mix(std::uint64_t h, const wg::PR5510_BatchWeigh& b) {
  const std::uint64_t v = static_cast<std::uint64_t>(b.State) | (std::uint64_t(b.CoarseFeed) << 8) |
                          (std::uint64_t(b.FineFeed) << 9) | (std::uint64_t(b.Discharge) << 10);
  return (h ^ v) * 0x100000001B3ULL;
}

// Closed loop, three batches, recording what the device sent each scan.
const Recording& recording() {
  static Recording rec = [] {
    Recording r;
    wtest::Cell c(plc::sim::Pr5510Config{});
    wg::PR5510_BatchWeigh b;
    setup(b, c.dev);
    c.idle(300ms);
    for (int i = 0; i < 5; ++i) {  // learn the preact first
      b.Execute = true;
      c.run_until([&] { return b.Done || b.Error; }, 60s, [&] { b(c.ctx); });
      b.Execute = false;
      c.scan([&] { b(c.ctx); });
    }
    r.dev_at_start = c.dev;
    r.batch_at_start = b;
    r.t0 = c.ctx.now;
    int done = 0;
    bool exec = true;
    while (done < 3) {
      std::array<std::uint8_t, 8> in{};
      std::copy(c.sim.r().begin(), c.sim.r().end(), in.begin());
      r.inputs.push_back(in);
      r.execute.push_back(exec);
      b.Execute = exec;
      c.scan([&] { b(c.ctx); });
      r.checksum = mix(r.checksum, b);
      if (exec && (b.Done || b.Error)) {
        exec = false;
        ++done;
      } else if (!exec) {
        exec = true;
      }
    }
    return r;
  }();
  return rec;
}

// Replays the recorded inputs into a fresh copy of the blocks.
struct Replay {
  explicit Replay(const Recording& r) : rec(r) { reset(); }
  void reset() {
    dev = rec.dev_at_start;
    link.set_state(plc::io::DeviceState::Online);
    dev.port.bind(in, out, &link);
    batch = rec.batch_at_start;
    batch.Device = &dev;
    ctx.now = rec.t0;
    i = 0;
  }
  const Recording& rec;
  wg::PR5510_Device dev;
  wg::PR5510_BatchWeigh batch;
  plc::io::DeviceLink link;
  std::array<std::uint8_t, 8> in{}, out{};
  plc::ScanContext ctx{};
  std::size_t i = 0;
};

void BM_BatchBlockPlusWindow(benchmark::State& state) {
  const Recording& rec = recording();
  Replay rp(rec);
  std::uint64_t sum = 0;
  bool checked = false;
  for (auto _ : state) {
    if (rp.i == rec.inputs.size()) {
      if (!checked && sum != rec.checksum) {
        state.SkipWithError("replay diverged from the recording");
        break;
      }
      checked = true;
      rp.reset();
    }
    rp.in = rec.inputs[rp.i];
    rp.batch.Execute = rec.execute[rp.i];
    ++rp.i;
    rp.ctx.now += 1ms;
    rp.dev(rp.ctx);
    rp.batch(rp.ctx);
    if (!checked) sum = mix(sum, rp.batch);
    benchmark::DoNotOptimize(rp.out);
  }
}
BENCHMARK(BM_BatchBlockPlusWindow)->Name("batch_block_plus_window_per_scan");

void BM_ReadValuePlusWindow(benchmark::State& state) {
  const Recording& rec = recording();
  Replay rp(rec);
  wg::PR5510_ReadValue rv;
  rv.Device = &rp.dev;
  rv.Enable = true;
  rv.Code = 0x09;
  for (auto _ : state) {
    if (rp.i == rec.inputs.size()) rp.i = 0;
    rp.in = rec.inputs[rp.i++];
    rp.ctx.now += 1ms;
    rp.dev(rp.ctx);
    rv(rp.ctx);
    benchmark::DoNotOptimize(rv.Value);
  }
}
BENCHMARK(BM_ReadValuePlusWindow)->Name("read_value_plus_window_per_scan");

void BM_ModelStep(benchmark::State& state) {
  plc::sim::Pr5510Model m{plc::sim::Pr5510Config{}};
  std::array<std::uint8_t, 8> w{}, r{};
  w[wg::w::kReadValueSelect] = 0x09;
  plc::TIME now{};
  std::int64_t n = 0;
  for (auto _ : state) {
    // Alternate fill and discharge so the load stays in range.
    w[wg::w::kOutputs] = ((n++ >> 12) & 1) ? 0x04 : 0x02;
    now += 1ms;
    m.step(now, 1ms, w, r);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_ModelStep)->Name("pr5510_model_step_per_ms");

void BM_ClosedLoop(benchmark::State& state) {
  wtest::Cell c(plc::sim::Pr5510Config{});
  wg::PR5510_BatchWeigh b;
  setup(b, c.dev);
  for (auto _ : state) {
    b.Execute = !(b.Done || b.Error);
    c.scan([&] { b(c.ctx); });
    benchmark::DoNotOptimize(b.ActualNet);
  }
}
BENCHMARK(BM_ClosedLoop)->Name("closed_loop_scan_per_ms");

// Prints `name: value ns` per benchmark and keeps the figures.
class LineReporter : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      // The coefficient of variation is a ratio, not a time: leave it out.
      if (r.run_type == Run::RT_Aggregate &&
          r.aggregate_unit == benchmark::StatisticUnit::kPercentage)
        continue;
      if (r.error_occurred) {
        std::printf("%s: error %s\n", r.benchmark_name().c_str(), r.error_message.c_str());
        continue;
      }
      const double ns = r.GetAdjustedRealTime();  // Unit is ns by default
      std::printf("%s: %.1f ns\n", r.benchmark_name().c_str(), ns);
      figures[r.benchmark_name()] = ns;
    }
  }
  std::map<std::string, double> figures;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  LineReporter rep;
  benchmark::RunSpecifiedBenchmarks(&rep);
  // With --benchmark_repetitions the median stands for the figure.
  for (const char* name : {"closed_loop_scan_per_ms", "closed_loop_scan_per_ms_median"}) {
    if (const auto it = rep.figures.find(name); it != rep.figures.end()) {
      std::printf("virtual_time_speedup: %.0f x\n", 1e6 / it->second);
      break;
    }
  }
  benchmark::Shutdown();
  return 0;
}

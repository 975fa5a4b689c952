// Retain costs (issue 14): the snapshot on the scan thread for 1,000 and
// 10,000 retained bytes (capture: every scan copies its task's retained
// values into the live buffer; offer: once per save period, the copy into
// the writer's buffer), and the writer's throughput (encode + temp file +
// fsync + rename + fsync of the folder) for the same sizes.
// Prints `name: value unit` lines.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "plc/retain/retain_file.hpp"
#include "plc/retain/retain_layout.hpp"
#include "plc/retain/retain_storage.hpp"
#include "plc/retain/retain_writer.hpp"
#include "plc_bench/collector.hpp"

namespace {

using namespace plc;

// `bytes` of retained DINTs (one task) in a registry of their own.
struct Fixture {
  explicit Fixture(std::size_t bytes) : values(bytes / 4) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      VarInfo v;
      v.path = "P.v[" + std::to_string(i) + "]";
      v.type = VarType::DINT;
      v.ptr = &values[i];
      v.task = 0;
      v.retain = RetainClass::Retain;
      vars.add(v);
    }
    layout = std::make_unique<retain::Layout>(vars, RetainConfig{}, image);
    live.resize(layout->bytes());
  }
  std::vector<DINT> values;
  VarRegistry vars;
  io::ProcessImage image;
  std::unique_ptr<retain::Layout> layout;
  std::vector<std::uint8_t> live;
};

void BM_Capture(benchmark::State& state) {
  Fixture f(std::size_t(state.range(0)));
  for (auto _ : state) {
    ++f.values[0];
    f.layout->capture(0, true, f.live);
    benchmark::DoNotOptimize(f.live.data());
  }
}
BENCHMARK(BM_Capture)->Arg(1000)->Arg(10000);

// The hand-over to an idle writer (a memcpy and a wake-up); the snapshot
// is unchanged, so the writer compares and writes nothing.
void BM_Offer(benchmark::State& state) {
  Fixture f(std::size_t(state.range(0)));
  const std::string path = "/tmp/bench_retain_offer_" + std::to_string(::getpid());
  retain::Storage storage(path);
  retain::Writer w(storage);
  retain::Writer::Slot slot(*f.layout);
  w.start(1);
  for (auto _ : state) {
    state.PauseTiming();  // the writer's side is not the scan's cost
    while (w.busy()) {
    }
    state.ResumeTiming();
    w.offer(slot, f.live);
  }
  w.stop(*f.layout, f.live);
  storage.discard();
}
BENCHMARK(BM_Offer)->Arg(1000)->Arg(10000);

void BM_Write(benchmark::State& state) {
  Fixture f(std::size_t(state.range(0)));
  const std::string path = "/tmp/bench_retain_write_" + std::to_string(::getpid());
  retain::Storage storage(path);
  std::vector<std::uint8_t> file;
  std::uint64_t seq = 1;
  for (auto _ : state) {
    ++f.values[0];
    f.layout->capture(0, true, f.live);
    retain::encode(*f.layout, f.live, seq, 0, file);
    if (!storage.write(file, seq).empty()) state.SkipWithError("write failed");
    ++seq;
  }
  state.counters["file_bytes"] = double(file.size());
  storage.discard();
}
BENCHMARK(BM_Write)->Arg(1000)->Arg(10000)->UseRealTime()->MinTime(1.0);

}  // namespace

int main(int argc, char** argv) {
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  for (const char* n : {"1000", "10000"}) {
    const std::string k = n;
    std::printf("retain_capture_%s_bytes: %.0f ns/save\n", n, c.cpu("BM_Capture/" + k));
    std::printf("retain_offer_%s_bytes: %.0f ns/save\n", n, c.cpu("BM_Offer/" + k));
    const double write_ns = c.wall("BM_Write/" + k + "/");
    std::printf("retain_write_%s_bytes: %.2f ms/file\n", n, write_ns / 1e6);
    std::printf("retain_write_%s_bytes_throughput: %.0f files/s\n", n,
                write_ns > 0 ? 1e9 / write_ns : 0.0);
  }
  return 0;
}

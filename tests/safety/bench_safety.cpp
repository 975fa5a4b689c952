// Benchmark: cost of the PROFIsafe F-host per F-module per scan, CRC
// included (issue acceptance), plus the parts it is made of.
// Prints one `name: value unit` line per figure.
//
//   profisafe_fmodule_per_scan      F_MODULE<4,4> (NORD size): check CRC2 of
//                                   the response, accept data, build the next
//                                   request with CRC2; responses precomputed
//   profisafe_nord_io_per_scan      the same through NORD_SAFE_IO (bit mapping)
//   profisafe_crc2_8byte_pdu        one CRC2 over a NORD PDU (4 data + CB + CN)
//   profisafe_host_and_sim_device_per_scan  F_MODULE plus the simulated NORD
//                                   device in lockstep (what a sim run costs)
#include <benchmark/benchmark.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "plc/fb/safety/control_status_byte.hpp"
#include "plc/fb/safety/f_module.hpp"
#include "plc/fb/safety/nord_safe_io.hpp"
#include "plc/fb/safety/safety_pdu.hpp"
#include "plc/io/sim_device.hpp"
#include "plc/sim/nord_profisafe_model.hpp"

namespace {

using namespace std::chrono_literals;
namespace ps = plc::safety;

std::unique_ptr<plc::io::SimDevice> make_device() {
  plc::io::ModelParams p;
  p.set("p802_3", "1");
  p.set("p802_1", "1");
  return std::make_unique<plc::io::SimDevice>(std::make_unique<plc::sim::NordProfisafeModel>(p));
}

// Brings an F-module to Run against the simulated device, then rebinds it to
// plain buffers; responses for the following consecutive numbers are then
// precomputed outside the timed loop (toggle and CN follow the protocol).
template <class Block, class FMod>
void run_host_only(benchmark::State& state, Block& blk, FMod& fm) {
  auto dev = make_device();
  dev->bind(fm.port);
  plc::ScanContext ctx{};
  for (int i = 0; i < 20; ++i) {
    ctx.now += 1ms;
    blk(ctx);
    dev->step(ctx.now, 1ms);
  }
  if (fm.STATE != ps::FHostState::Run) {
    state.SkipWithError("F-module did not reach Run");
    return;
  }
  std::array<std::uint8_t, 8> in{}, out{};
  std::memcpy(in.data(), dev->inputs().data(), 8);
  std::memcpy(out.data(), dev->outputs().data(), 8);
  plc::io::DeviceLink link;
  link.set_state(plc::io::DeviceState::Online);
  fm.port.bind(in, out, &link);

  constexpr int kBatch = 1024;
  std::vector<std::array<std::uint8_t, 8>> resp(kBatch);
  const std::uint16_t crc1 =
      static_cast<std::uint16_t>((fm.fparam_block()[12] << 8) | fm.fparam_block()[13]);
  const std::array<std::uint8_t, 4> data = {0x00, 0x80, 0x00, 0x30};
  for (auto _ : state) {
    std::uint32_t cn = fm.protocol().cons_nr();
    bool toggle = (out[4] & ps::cb::kToggleH) != 0;
    for (int j = 0; j < kBatch; ++j) {
      ps::write_pdu(resp[j], data, toggle ? ps::sb::kToggleD : 0, cn, crc1);
      cn = ps::next_cons_nr(cn);
      toggle = !toggle;
    }
    const auto t0 = std::chrono::steady_clock::now();
    for (int j = 0; j < kBatch; ++j) {
      std::memcpy(in.data(), resp[j].data(), 8);
      ctx.now += 1ms;
      blk(ctx);
    }
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(out);
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
  }
  // One iteration is a batch of kBatch scans; the reporter divides.
  state.counters["scans_per_iteration"] = kBatch;
  if (fm.STATE != ps::FHostState::Run || fm.QBAD) state.SkipWithError("left Run during bench");
}

void profisafe_fmodule_per_scan(benchmark::State& state) {
  ps::F_MODULE<4, 4> fm;
  fm.OUT_DATA[0] = 0x01;
  run_host_only(state, fm, fm);
}
BENCHMARK(profisafe_fmodule_per_scan)->UseManualTime();

void profisafe_nord_io_per_scan(benchmark::State& state) {
  ps::NORD_SAFE_IO io;
  io.OSSD1 = true;
  run_host_only(state, io, io.FMOD);
}
BENCHMARK(profisafe_nord_io_per_scan)->UseManualTime();

void profisafe_crc2_8byte_pdu(benchmark::State& state) {
  std::array<std::uint8_t, 4> d = {1, 2, 3, 4};
  std::uint32_t cn = 1;
  for (auto _ : state) {
    benchmark::DoNotOptimize(d);
    auto c = ps::compute_crc2(d, 0x20, cn, 0x32CB);
    benchmark::DoNotOptimize(c);
    cn = ps::next_cons_nr(cn);
  }
}
BENCHMARK(profisafe_crc2_8byte_pdu);

void profisafe_host_and_sim_device_per_scan(benchmark::State& state) {
  auto dev = make_device();
  ps::F_MODULE<4, 4> fm;
  fm.OUT_DATA[0] = 0x01;
  dev->bind(fm.port);
  plc::ScanContext ctx{};
  for (auto _ : state) {
    ctx.now += 1ms;
    fm(ctx);
    dev->step(ctx.now, 1ms);
  }
  // (Google Benchmark first probes with one iteration: still in start-up.)
  if (state.iterations() > 100 && fm.STATE != ps::FHostState::Run)
    state.SkipWithError("not in Run");
}
BENCHMARK(profisafe_host_and_sim_device_per_scan);

// Prints `name: value ns` per benchmark.
class LineReporter : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      // With --benchmark_repetitions only the mean and median are figures.
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name != "mean" &&
          r.aggregate_name != "median")
        continue;
      if (r.error_occurred) {
        std::printf("%s: error %s\n", r.benchmark_name().c_str(), r.error_message.c_str());
        continue;
      }
      double per = 1.0;
      if (auto it = r.counters.find("scans_per_iteration"); it != r.counters.end())
        per = it->second.value;
      const double ns = r.GetAdjustedRealTime() / per *
                        (r.time_unit == benchmark::kNanosecond    ? 1.0
                         : r.time_unit == benchmark::kMicrosecond ? 1e3
                         : r.time_unit == benchmark::kMillisecond ? 1e6
                                                                  : 1e9);
      std::string name = r.benchmark_name();
      if (auto p = name.find('/'); p != std::string::npos) name = name.substr(0, p);
      const std::string suffix = "_" + r.aggregate_name;
      if (r.run_type == Run::RT_Aggregate &&
          (name.size() < suffix.size() ||
           name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0))
        name += suffix;
      std::printf("%s: %.1f ns\n", name.c_str(), ns);
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  LineReporter rep;
  benchmark::RunSpecifiedBenchmarks(&rep);
  benchmark::Shutdown();
  return 0;
}

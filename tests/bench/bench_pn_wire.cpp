// PROFINET codec costs on the cyclic path (iec-io/profinet/wire/cyclic.hpp):
// encoding one RT_CLASS_1 frame (the E1's telegram-111 output CR: DAP IOCS
// + 24 bytes data + IOPS, padded to 40) into a caller buffer, and decoding
// it plus reading its data and IOPS, without allocation; and one such frame
// through the in-memory hub (link/memory_ethernet.hpp) of the PROFINET
// filling cell's three ports (controller, conveyor, safety module): sent by
// the controller, received by both others (a hub shows every port every
// frame), as each cyclic frame of `simulate: true` goes.
// Prints `name: value unit` lines.
#include <benchmark/benchmark.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <vector>

#include "plc/profinet/link/memory_ethernet.hpp"
#include "plc/profinet/wire/cyclic.hpp"
#include "plc_bench/collector.hpp"

namespace {

namespace pn = plc::profinet;

std::vector<pn::ExpectedSubmoduleBlockReq> e1_submodules() {
  pn::ExpectedSubmoduleBlockReq dap, drive;
  dap.modules.push_back(
      {0,
       0,
       1,
       0,
       {{1, 1, 0, 0, 0, 1, 1}, {0x8000, 2, 0, 0, 0, 1, 1}, {0x8001, 3, 0, 0, 0, 1, 1}}});
  drive.modules.push_back({0x3A00, 1, 0x111, 0, {{1, 0x111, 0, 24, 24, 1, 1}}});
  return {dap, drive};
}

struct Fixture {
  pn::CyclicLayout layout;
  std::array<std::uint8_t, pn::kMaxFrameLength> frame{};
  std::array<std::uint8_t, 24> data{};
  pn::CyclicHeader h{
      {0x02, 0, 0, 0, 0, 2}, {0x02, 0, 0, 0, 0, 1}, std::nullopt, 0xC002, 0, 0x35, 0};
  Fixture() { (void)pn::compute_layout(e1_submodules(), layout); }
  std::size_t encode() {
    const auto& cr = layout.output;
    auto c_sdu = pn::cyclic_c_sdu(frame, cr.c_sdu_length, false);
    std::fill(c_sdu.begin(), c_sdu.end(), std::uint8_t{0});
    for (const auto& o : cr.data) pn::put_io_data(c_sdu, o, data, pn::iocr::kIoxsGood);
    for (const auto& s : cr.iocs) c_sdu[s.offset] = pn::iocr::kIoxsGood;
    ++h.cycle_counter;
    return pn::finish_cyclic(frame, h, cr.c_sdu_length);
  }
};

void BM_EncodeCyclicFrame(benchmark::State& state) {
  Fixture f;
  for (auto _ : state) {
    ++f.data[0];
    benchmark::DoNotOptimize(f.encode());
  }
}
BENCHMARK(BM_EncodeCyclicFrame)->MinTime(0.2);

void BM_DecodeCyclicFrame(benchmark::State& state) {
  Fixture f;
  const std::size_t n = f.encode();
  const auto& cr = f.layout.output;
  for (auto _ : state) {
    pn::CyclicView v;
    const auto st = pn::decode_cyclic(std::span(f.frame).first(n), cr.c_sdu_length, v);
    benchmark::DoNotOptimize(st);
    for (const auto& o : cr.data) {
      benchmark::DoNotOptimize(pn::io_data(v.c_sdu, o).data());
      benchmark::DoNotOptimize(pn::iops(v.c_sdu, o));
    }
  }
}
BENCHMARK(BM_DecodeCyclicFrame)->MinTime(0.2);

void BM_HubCyclicFrame(benchmark::State& state) {
  Fixture f;
  const std::size_t n = f.encode();
  pn::MemoryEthernet hub;
  const auto ctrl = hub.port(f.h.src);
  const auto conveyor = hub.port(f.h.dst);
  const auto safety = hub.port();
  std::array<std::uint8_t, pn::kMaxFrameLength> rx{};
  const auto frame = std::span<const std::uint8_t>(f.frame).first(n);
  for (auto _ : state) {
    benchmark::DoNotOptimize(ctrl->send(frame));
    benchmark::DoNotOptimize(conveyor->receive(rx, std::chrono::nanoseconds(0)));
    benchmark::DoNotOptimize(safety->receive(rx, std::chrono::nanoseconds(0)));
  }
  if (conveyor->counters().received != safety->counters().received ||
      conveyor->counters().received != ctrl->counters().sent)
    state.SkipWithError("a frame did not reach every port");
}
BENCHMARK(BM_HubCyclicFrame)->MinTime(0.2);

}  // namespace

int main(int argc, char** argv) {
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  std::printf("pn_cyclic_frame_encode: %.0f ns\n", c.cpu("BM_EncodeCyclicFrame"));
  std::printf("pn_cyclic_frame_decode: %.0f ns\n", c.cpu("BM_DecodeCyclicFrame"));
  std::printf("pn_hub_cyclic_frame: %.0f ns\n", c.cpu("BM_HubCyclicFrame"));
  return 0;
}

// PROFINET codec costs on the cyclic path (iec-io/profinet/wire/cyclic.hpp):
// encoding one RT_CLASS_1 frame (the E1's telegram-111 output CR: DAP IOCS
// + 24 bytes data + IOPS, padded to 40) into a caller buffer, and decoding
// it plus reading its data and IOPS, without allocation.
// Prints `name: value unit` lines.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdio>
#include <iostream>
#include <map>
#include <vector>

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

}  // namespace

int main(int argc, char** argv) {
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  std::printf("pn_cyclic_frame_encode: %.0f ns\n", c.cpu("BM_EncodeCyclicFrame"));
  std::printf("pn_cyclic_frame_decode: %.0f ns\n", c.cpu("BM_DecodeCyclicFrame"));
  return 0;
}

// The HMI benchmarks' cell (bench_hmi, bench_web_hmi): one 1 ms task whose
// program P changes 1,000 DINTs every scan (a fixed-seed xorshift), all
// published to the HMI; the worst case for the bridge's copy and encode.
// The program registers itself: include this in one source file of an
// executable.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "plc/cell_config.hpp"
#include "plc/program.hpp"

namespace plc::bench {

class ThousandVars : public ProgramBase<ThousandVars> {
 public:
  std::array<DINT, 1000> vals{};
  std::uint32_t x = 2463534242u;
  void cycle(const ScanContext&) override {
    for (auto& e : vals) {
      x ^= x << 13;
      x ^= x >> 17;
      x ^= x << 5;
      e = DINT(x % 100000);
    }
  }
  PLC_REFLECT(vals)
};
PLC_REGISTER_PROGRAM(ThousandVars)

inline constexpr const char* kThousandVarsCell = R"(
cell: bench
tasks: [{name: main, period: 1ms, watchdog: 0, programs: [P]}]
programs: [{name: P, type: ThousandVars}]
)";

// The hmi: section that publishes P's 1,000 variables at `rate` per second.
inline HmiConfig thousand_vars_hmi(const std::string& url, int rate) {
  HmiConfig h;
  h.present = true;
  h.url.value = url;
  h.rate.value = rate;
  h.publish = {{"P.vals*", {}}};
  return h;
}

}  // namespace plc::bench

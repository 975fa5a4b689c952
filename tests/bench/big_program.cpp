// A 1,000-FB program for the online-change benchmark (bench_online_change):
// 250 each of TON, R_TRIG, CTU and TOF with inputs that keep them busy.
// Built twice (BIG_VERSION 1 and 2); version 2 adds a field, so the switch
// does the whole compare-and-copy over every FB's state.
#include <array>

#include "plc/fb/iec/iec.hpp"
#include "plc/program.hpp"

using namespace plc;
using namespace std::chrono_literals;

class Big : public ProgramBase<Big> {
 public:
  DINT n = 0;
#if BIG_VERSION == 2
  DINT added = 0;
#endif
  std::array<iec::TON, 250> tons;
  std::array<iec::R_TRIG, 250> trigs;
  std::array<iec::CTU, 250> ctus;
  std::array<iec::TOF, 250> tofs;

  void cycle(const ScanContext& ctx) override {
    ++n;
    for (std::size_t i = 0; i < 250; ++i) {
      tons[i](ctx, ((n + DINT(i)) / 32) % 2 == 0, 20ms);
      trigs[i](((n * 7 + DINT(i)) % 3) == 0);
      ctus[i](trigs[i].Q, false, 1000);
      tofs[i](ctx, tons[i].Q, 10ms);
    }
  }

#if BIG_VERSION == 2
  PLC_REFLECT(n, added, tons, trigs, ctus, tofs)
#else
  PLC_REFLECT(n, tons, trigs, ctus, tofs)
#endif
};
PLC_REGISTER_PROGRAM(Big)

// Issue 21 follow-up, point 9: FillingCellAc retries a fault reset that the
// drive never saw. Virtual time: the VF66B (in-process sim model) trips a
// fault at 12 s, once the first container is filled (about 10 s); the
// first reset pulse (100 ms, AcDrive.ResetPulse) falls in a gap
// of the drive's polls (the test hides the Fault Reset bit of output
// assembly 21, byte 0 bit 2, from the drive for 300 ms from its first
// rising edge, as a late poll cycle would). Before, the program held
// FaultReset high - no new edge, no new pulse - and the cell stayed in its
// fault step for good; now it drops the request after reset_pause and
// raises it again, the drive resets and the cell fills containers again.
#include <gtest/gtest.h>

#include <string>

#include "plc/cell_config.hpp"
#include "plc/fb/acdrive/assemblies.hpp"
#include "plc/runtime.hpp"

using namespace plc;
using namespace std::chrono_literals;

namespace {

const char* kCell = R"(
cell: filling-ac
image: {inputs: 256, outputs: 256, memory: 64}
tasks: [{name: main, period: 1ms, programs: [Cell]}]
programs: [{name: Cell, type: FillingCellAc}]
plugins: [{name: sim}]
devices:
  - {name: conveyor, plugin: sim, model: vf66b, input: "%IB0", output: "%QB0",
     params: {j09: 1, j10: 1, b10: 3, b11: 3, accel_time: 500ms, decel_time: 500ms,
              fault_code: 5, fault_at: 12s}}
  - {name: scale, plugin: sim, model: pr5510, input: "%IB32", output: "%QB32",
     params: {bus: profibus, coarse_rate: 4.0, fine_rate: 0.4, noise: 0.002, seed: 7}}
  - name: safety
    plugin: sim
    model: nord_profisafe
    input: "%IB48"
    output: "%QB48"
    params: {dip_address: 1, p802_3: 1, p840: 0}
)";

// Hides the drive's Fault Reset bit from the drive (what it receives) for
// `gap` from its first rising edge on.
class LatePoll : public ScanHooks {
 public:
  explicit LatePoll(TIME gap) : gap_(gap) {}
  void before_publish(TaskRuntime& t, io::ProcessImage& global) override {
    std::uint8_t& b = global.area(io::Area::Output)[0];
    const bool bit = b & acdrive::Output21::kFaultReset;
    if (bit && !prev_ && !seen_) {
      seen_ = true;
      from_ = t.scan_time;
    }
    prev_ = bit;
    if (seen_ && t.scan_time - from_ < gap_) {
      b = static_cast<std::uint8_t>(b & ~acdrive::Output21::kFaultReset);
      ++hidden;
    }
  }
  int hidden = 0;

 private:
  TIME gap_, from_{};
  bool prev_ = false, seen_ = false;
};

std::string v(const Runtime& rt, const std::string& path) {
  const VarInfo* x = rt.vars().find(path);
  return x ? VarRegistry::format(*x) : "<none>";
}

TEST(FillingCellAc, AResetPulseTheDriveMissedIsRetried) {
  Runtime rt(parse_cell_config(kCell, "filling_ac.yaml"));
  LatePoll late(300ms);
  rt.add_hooks(&late);
  rt.start(io::ClockMode::Virtual);
  auto run_until = [&](auto&& pred, TIME limit) {
    const TIME end = rt.now() + limit;
    while (!pred() && rt.now() < end) rt.tick();
    return pred();
  };
  ASSERT_TRUE(run_until([&] { return v(rt, "Cell.containers") != "0"; }, 60s))
      << "the cell never filled a container";
  ASSERT_TRUE(run_until([&] { return v(rt, "Cell.step") == "9"; }, 30s)) << "no drive fault";
  ASSERT_TRUE(run_until([&] { return late.hidden > 0; }, 5s)) << "no reset pulse";
  const std::string before = v(rt, "Cell.containers");
  // Out of the fault step within a few retries, and filling again.
  EXPECT_TRUE(run_until([&] { return v(rt, "Cell.step") != "9"; }, 20s))
      << "stuck in the fault step; drive Faulted " << v(rt, "Cell.conveyor.Faulted");
  EXPECT_EQ(v(rt, "Cell.conveyor.Faulted"), "FALSE");
  EXPECT_TRUE(run_until([&] { return v(rt, "Cell.containers") != before; }, 60s));
  rt.finish();
}

}  // namespace

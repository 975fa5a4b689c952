// Test harness for the blocks: a PR5510_Device bound to a simulated PR5510,
// one scan per virtual millisecond: device block, the test's blocks, then
// the device model (as the lockstep sim plugin does).
#pragma once

#include "plc/fb/weighing/pr5510_device.hpp"
#include "pr5510_harness.hpp"

namespace wtest {

struct Cell {
  explicit Cell(const plc::sim::Pr5510Config& c) : sim(c) {
    sim.dev.bind(dev.port);
    dev.BusType = c.bus;
    dev.PackedWordOrder = c.packed_order;
    ctx.period = 1ms;
  }

  // One scan: `body` calls the blocks under test.
  template <class F>
  void scan(F&& body) {
    ctx.now += 1ms;
    dev(ctx);
    body();
    sim.dev.step(ctx.now, 1ms);
    ++ctx.cycle;
  }
  template <class F>
  void run(std::chrono::milliseconds ms, F&& body) {
    for (std::int64_t i = 0; i < ms.count(); ++i) scan(body);
  }
  void idle(std::chrono::milliseconds ms) {
    run(ms, [] {});
  }
  // Scans until pred() holds (checked after each scan) or `limit` passes.
  // Returns the virtual time it took, or -1 ms on timeout.
  template <class P, class F>
  std::chrono::milliseconds run_until(P&& pred, std::chrono::milliseconds limit, F&& body) {
    for (std::int64_t i = 1; i <= limit.count(); ++i) {
      scan(body);
      if (pred()) return std::chrono::milliseconds(i);
    }
    return std::chrono::milliseconds(-1);
  }

  plc::sim::Pr5510Model& model() { return sim.model; }

  Harness sim;
  plc::weighing::PR5510_Device dev;
  plc::ScanContext ctx{};
};

}  // namespace wtest

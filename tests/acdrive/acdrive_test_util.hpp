// Virtual-time harness for the AC drive block tests: one simulated VF66B in
// lockstep with the scan (the sim plugin's order: scan, then device step).
#pragma once

#include <functional>
#include <memory>

#include "plc/fb/acdrive/ac_drive.hpp"
#include "plc/io/sim_device.hpp"
#include "plc/scan_context.hpp"
#include "vf66b/vf66b_model.hpp"

namespace plc::acdrive::test {

using namespace std::chrono_literals;

// Network control and reference (b-10 = b-11 = 3), quick ramps.
inline sim::Vf66bConfig net_config(unsigned j09 = 1, unsigned j10 = 1) {
  sim::Vf66bConfig c;
  c.j09 = j09;
  c.j10 = j10;
  c.b10 = 3;
  c.b11 = 3;
  c.startup_time = 50ms;
  c.accel_time_s = 1;  // 0 -> 1800 rpm in 1 s
  c.decel_time_s = 1;
  c.coast_time_s = 0.5;
  return c;
}

struct Bench {
  explicit Bench(const sim::Vf66bConfig& cfg = net_config()) {
    auto m = std::make_unique<sim::Vf66bModel>(cfg);
    model = m.get();
    dev = std::make_unique<io::SimDevice>(std::move(m));
    fb.OutputInstance = output_instance(cfg.j09);
    fb.InputInstance = input_instance(cfg.j10);
    fb.SpeedScale = static_cast<SINT>(cfg.j11);
    fb.TopSpeed = cfg.top_speed_rpm;
    fb.J12 = static_cast<USINT>(cfg.j12);
    dev->bind(fb.Port);
    dev->step(ctx.now, period);
  }
  // One scan: the program (the block, then `extra`), then the drive steps.
  void scan(const std::function<void()>& extra = {}) {
    fb(ctx);
    if (extra) extra();
    ctx.now += period;
    ++ctx.cycle;
    dev->step(ctx.now, period);
  }
  bool run_until(const std::function<bool()>& pred, int max_scans = 10000,
                 const std::function<void()>& extra = {}) {
    for (int i = 0; i < max_scans; ++i) {
      scan(extra);
      if (pred()) return true;
    }
    return false;
  }
  void run(int scans) {
    for (int i = 0; i < scans; ++i) scan();
  }
  ScanContext ctx{TIME{}, 1ms, 0};
  TIME period = 1ms;
  sim::Vf66bModel* model = nullptr;
  std::unique_ptr<io::SimDevice> dev;
  AcDrive fb;
};

}  // namespace plc::acdrive::test

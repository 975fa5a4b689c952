// Virtual-time harness for the drive tests: one simulated E1 in lockstep
// with the scan (the sim plugin's order: scan, then device step).
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <vector>

#include "hiwin_e1/hiwin_e1_model.hpp"
#include "plc/fb/drive/drive_axis.hpp"
#include "plc/io/sim_device.hpp"
#include "plc/scan_context.hpp"

namespace plc::drive::test {

using namespace std::chrono_literals;

struct Bench {
  explicit Bench(sim::HiwinE1Config cfg = {}, UINT telegram = 111) {
    cfg.telegram = static_cast<TelegramType>(telegram);
    auto m = std::make_unique<sim::HiwinE1Model>(cfg);
    model = m.get();
    dev = std::make_unique<io::SimDevice>(std::move(m));
    axis.Telegram = telegram;
    dev->bind(axis.Port);
    dev->step(ctx.now, period);  // first frame from the drive
  }
  // One scan: the program (body), then the drive steps one period.
  void scan(const std::function<void()>& body) {
    body();
    watch();
    ctx.now += period;
    ++ctx.cycle;
    dev->step(ctx.now, period);
  }
  // What the program sent, scan by scan (STW1.0/.3/.7 are the same bits in
  // every telegram): rising edges of STW1.7 (fault acknowledge), and scans
  // in which STW1 asked for ON or enable operation while the axis was in
  // ErrorStop (PLCopen state diagram: never).
  void watch() {
    const bool ack = (axis.STW1 & Stw1Pos::kFaultAck) != 0;
    if (ack && !prev_ack) ++ack_edges;
    prev_ack = ack;
    if (axis.State == AxisState::ErrorStop &&
        (axis.STW1 & (Stw1Pos::kOn | Stw1Pos::kEnableOperation)) != 0)
      ++power_in_error_stop;
  }
  // Scans until pred() or max scans; returns true if pred() became true.
  bool run_until(const std::function<void()>& body, const std::function<bool()>& pred,
                 int max_scans = 10000) {
    for (int i = 0; i < max_scans; ++i) {
      scan(body);
      if (pred()) return true;
    }
    return false;
  }
  void run(const std::function<void()>& body, int scans) {
    for (int i = 0; i < scans; ++i) scan(body);
  }
  // The no-automatic-restart check: runs `scans` scans and fails (with the
  // scan number) as soon as STW1 asks for ON or enable operation, or the
  // drive reaches S4. STW1 bits 0 and 3 are the same in every telegram.
  ::testing::AssertionResult stays_off(const std::function<void()>& body, int scans) {
    for (int i = 0; i < scans; ++i) {
      scan(body);
      if ((axis.STW1 & (Stw1Pos::kOn | Stw1Pos::kEnableOperation)) != 0)
        return ::testing::AssertionFailure() << "STW1 asks for power in scan " << i;
      if (model->state() == sim::HiwinE1Model::State::S4)
        return ::testing::AssertionFailure() << "the drive is in S4 in scan " << i;
    }
    return ::testing::AssertionSuccess();
  }
  int ack_edges = 0;
  int power_in_error_stop = 0;
  bool prev_ack = false;
  // Runs until the axis is in Standstill with the drive in operation (S4),
  // at most `scans` scans; `path` gets the drive states passed on the way
  // (each change once, starting with the present one).
  bool until_standstill(const std::function<void()>& body, int scans,
                        std::vector<sim::HiwinE1Model::State>* path = nullptr) {
    if (path) path->assign(1, model->state());
    for (int i = 0; i < scans; ++i) {
      scan(body);
      if (path && path->back() != model->state()) path->push_back(model->state());
      if (axis.State == AxisState::Standstill && model->state() == sim::HiwinE1Model::State::S4)
        return true;
    }
    return false;
  }
  ScanContext ctx{TIME{}, 1ms, 0};
  TIME period = 1ms;
  sim::HiwinE1Model* model = nullptr;
  std::unique_ptr<io::SimDevice> dev;
  DriveAxis axis;
};

}  // namespace plc::drive::test

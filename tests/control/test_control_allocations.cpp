// The control blocks allocate nothing in a scan (DESIGN.md: no heap
// allocation inside cycle()/FB calls): PID_Compact in manual and in
// automatic with its D filter and PWM output, CONT_C with its D path, and a
// whole PID_StepTune run (baseline, step, the least-squares iterations of
// the identification) on a plant from the plant core.
#include <gtest/gtest.h>

#include "../plant/allocation_counter.hpp"
#include "loop_harness.hpp"
#include "plc/fb/control/cont_c.hpp"
#include "plc/fb/control/pid_compact.hpp"
#include "plc/fb/control/pid_step_tune.hpp"

namespace pc = plc::control;
using namespace control_test;

namespace {

TEST(ControlBlocks, CallsAllocateNothing) {
  if (!plant_test::counting()) GTEST_SKIP() << "a sanitizer owns malloc";
  // The oven of test_tuning.cpp at rest at 10 %, every block called every
  // 100 ms; no vector grows in this loop (the Loop harness records, so it
  // is not used here).
  auto plant = fopdt(2.0, 60.0, 5s, 100ms, 10.0);
  pc::PID_StepTune tune;
  tune.BaseOutput = 10.0f;
  tune.StepSize = 20.0f;
  tune.SettleTime = 20s;
  tune.TestTime = 300s;
  pc::PID_Compact pid;
  pid.Gain = 2.5f;
  pid.Ti = 44.0f;
  pid.Td = 2.0f;
  pid.InputUpperLimit = 300.0f;
  pc::CONT_C cont;
  cont.MAN_ON = false;
  cont.D_SEL = true;
  cont.CYCLE = plc::TIME(0);
  plc::ScanContext ctx{};
  ctx.period = 100ms;

  const std::size_t before = plant_test::allocations();
  for (int k = 0; k < 6000; ++k) {
    const double pv = plant.outputs()[0] + 20.0;
    tune.Execute = true;
    tune.Input = static_cast<plc::REAL>(pv);
    tune(ctx);
    pid.ManualEnable = !tune.Done;
    pid.ManualValue = tune.Output;
    pid.Setpoint = 60.0f;
    pid.Input = static_cast<plc::REAL>(pv);
    pid(ctx);
    cont.SP_INT = 60.0f;
    cont.PV_IN = static_cast<plc::REAL>(pv);
    cont(ctx);
    const double u[1] = {double(pid.Output)};
    plant.step(u);
    ctx.now += 100ms;
    ++ctx.cycle;
  }
  const std::size_t after = plant_test::allocations();
  EXPECT_EQ(after, before);
  // The counted stretch held the whole step test and automatic mode.
  EXPECT_TRUE(tune.Done) << "ErrorID " << std::hex << std::uint16_t(tune.ErrorID);
  EXPECT_GT(tune.Iterations, 0);
  EXPECT_EQ(pid.State, plc::INT(pc::PID_Compact::Mode::Automatic));
}

}  // namespace

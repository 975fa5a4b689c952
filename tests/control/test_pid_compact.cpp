// PID_Compact on a plant model in virtual time: the closed loop's overshoot
// and settling time, anti-windup after a long saturation, bumpless manual ->
// automatic, cycle-time independence, derivative on the measurement with
// its filter, the setpoint ramp, PWM and the error reactions (ErrorBits as
// in the PID_Compact manual's ErrorBits table, A5E35300227).
#include <gtest/gtest.h>

#include <cmath>

#include "loop_harness.hpp"
#include "plc/fb/control/error_bits.hpp"
#include "plc/fb/control/pid_compact.hpp"

namespace pc = plc::control;
using namespace control_test;
using plc::INT;
using plc::TIME;

namespace {

// The oven of these tests: 2 degC per % heater, T = 60 s, L = 5 s, 20 degC
// ambient. SIMC with the default tau_c = max(L, T / 10) = 6 s:
// Kc = 60 / (2 (6 + 5)) = 2.73, Ti = min(60, 44) = 44 s (TuningRules.*).
constexpr double kK = 2.0, kT = 60.0, kAmbient = 20.0;
constexpr TIME kL = 5s;

Loop oven(TIME period) {
  Loop l(fopdt(kK, kT, kL, 10ms), period);
  l.offset = kAmbient;
  return l;
}

pc::PID_Compact simc_pid() {
  pc::PID_Compact p;
  p.Gain = static_cast<plc::REAL>(60.0 / 22.0);
  p.Ti = 44.0f;
  p.Td = 0.0f;
  p.InputUpperLimit = 300.0f;
  return p;
}

// Runs the loop with `pid`: setpoint `sp`.
void run(Loop& l, pc::PID_Compact& pid, double sp, TIME span) {
  l.run(span, [&](const plc::ScanContext& ctx, double pv) {
    pid.Setpoint = static_cast<plc::REAL>(sp);
    pid.Input = static_cast<plc::REAL>(pv);
    pid(ctx);
    return double(pid.Output);
  });
}

// Holds the oven in manual at `u` % until it is steady.
void settle_manual(Loop& l, pc::PID_Compact& pid, double u) {
  pid.ManualEnable = true;
  pid.ManualValue = static_cast<plc::REAL>(u);
  run(l, pid, l.pv(), 900s);
  pid.ManualEnable = false;
}

TEST(PidCompact, ClosedLoopSetpointStepOvershootAndSettling) {
  // From steady state at 40 degC (10 %), in automatic, a setpoint step to
  // 50 degC, the PID called every 100 ms. Stated acceptance: overshoot at
  // most 10 %, within +-2 % of the step after at most 120 s (2 T; the plant
  // alone takes 5 + 4 x 60 = 245 s to get within 2 %). SIMC's PI on this
  // plant gives about 7 % and 70 s (Skogestad 2003 expects about 10 % for
  // Ti < T).
  Loop l = oven(100ms);
  auto pid = simc_pid();
  settle_manual(l, pid, 10.0);
  ASSERT_NEAR(l.pv(), 40.0, 0.01);
  // Automatic at the old setpoint first: switching to automatic with the new
  // one would be bumpless and take the P kick away from the step.
  run(l, pid, 40.0, 10s);
  const std::size_t from = l.y.size();
  run(l, pid, 50.0, 600s);
  const auto f = step_figures(l, from, 40.0, 50.0, 2.0);
  std::printf("closed loop: overshoot %.2f %%, settling (2 %%) %.1f s, final %.4f\n",
              f.overshoot_percent, f.settling_s, l.pv());
  EXPECT_LE(f.overshoot_percent, 10.0);
  EXPECT_LE(f.settling_s, 120.0);
  EXPECT_NEAR(l.pv(), 50.0, 0.01);
  EXPECT_EQ(pid.State, INT(pc::PID_Compact::Mode::Automatic));
  EXPECT_FALSE(pid.Error);
}

TEST(PidCompact, AntiWindupAfterALongSaturation) {
  // 600 s asking for 250 degC, which 100 % heater (220 degC) cannot give:
  // the output sits at its limit all the time. Then 100 degC: without
  // anti-windup the integral would have grown by Kc/Ti x 30 K x 600 s =
  // 1350 % and hold the heater at 100 % for minutes; with it the output
  // leaves the limit as soon as the error turns, and the overshoot stays
  // small.
  Loop l = oven(100ms);
  auto pid = simc_pid();
  run(l, pid, 250.0, 600s);
  EXPECT_EQ(pid.Output, 100.0f);
  EXPECT_LE(pid.IAction, 100.0f) << "the integral action wound up beyond the output range";
  const double hot = l.pv();
  ASSERT_GT(hot, 200.0);
  const std::size_t from = l.y.size();
  run(l, pid, 100.0, 900s);
  // The output left the 100 % limit at the first call after the change.
  EXPECT_LT(l.out[from], 100.0);
  const auto f = step_figures(l, from, hot, 100.0, 2.0);
  std::printf("after saturation: undershoot %.2f %%, settling %.1f s\n", f.overshoot_percent,
              f.settling_s);
  EXPECT_LE(f.overshoot_percent, 10.0);
  EXPECT_LE(f.settling_s, 300.0);
  EXPECT_NEAR(l.pv(), 100.0, 0.05);
}

TEST(PidCompact, ManualToAutomaticIsBumpless) {
  Loop l = oven(100ms);
  auto pid = simc_pid();
  settle_manual(l, pid, 35.0);  // 90 degC
  const std::size_t from = l.y.size();
  run(l, pid, 60.0, 1s);  // automatic with the setpoint 30 K below
  // The first automatic output is the last manual one; then it moves
  // smoothly (the P action changes only with the measurement).
  EXPECT_FLOAT_EQ(l.out[from], 35.0f);
  for (std::size_t i = from + 1; i < l.out.size(); ++i)
    EXPECT_NEAR(l.out[i], l.out[i - 1], 0.5) << "a bump at call " << i - from;
  EXPECT_EQ(pid.State, INT(pc::PID_Compact::Mode::Automatic));
}

TEST(PidCompact, ResponseDoesNotDependOnTheCallPeriod) {
  // The same gains called every 10 ms, 100 ms and 500 ms: the closed-loop
  // responses agree within 1.5 % of the step at every common instant (the
  // slower the calls, the later the controller sees the plant; a 500 ms
  // call adds about 250 ms of average delay to a loop with 5 s dead time).
  std::vector<Loop> loops;
  for (TIME p : {10ms, 100ms, 500ms}) {
    Loop l = oven(p);
    auto pid = simc_pid();
    settle_manual(l, pid, 10.0);
    const std::size_t from = l.y.size();
    run(l, pid, 50.0, 300s);
    l.t.erase(l.t.begin(), l.t.begin() + static_cast<std::ptrdiff_t>(from));
    l.y.erase(l.y.begin(), l.y.begin() + static_cast<std::ptrdiff_t>(from));
    loops.push_back(std::move(l));
  }
  auto at = [](const Loop& l, double dt) {
    const double t0 = l.t.front();
    for (std::size_t i = 0; i < l.t.size(); ++i)
      if (l.t[i] - t0 >= dt - 1e-9) return l.y[i];
    return l.y.back();
  };
  double worst = 0;
  for (double s = 0; s <= 299; s += 0.5) {
    const double ref = at(loops[0], s);
    for (std::size_t k = 1; k < loops.size(); ++k)
      worst = std::max(worst, std::fabs(at(loops[k], s) - ref));
  }
  std::printf("largest difference between call periods: %.3f K of a 10 K step\n", worst);
  EXPECT_LE(worst, 0.15);
}

TEST(PidCompact, DerivativeActsOnTheMeasurementOnlyByDefault) {
  plc::ScanContext ctx{};
  ctx.period = 100ms;
  pc::PID_Compact pid;
  pid.Gain = 2.0f;
  pid.Ti = 0.0f;
  pid.Td = 10.0f;
  pid.Input = 50.0f;
  pid.Setpoint = 50.0f;
  pid(ctx);  // bumpless start
  ctx.now += 100ms;
  pid(ctx);
  pid.Setpoint = 60.0f;  // a setpoint step: no derivative kick with c = 0
  ctx.now += 100ms;
  pid(ctx);
  EXPECT_EQ(pid.DAction, 0.0f);
  EXPECT_NEAR(pid.PAction, 20.0f, 1e-5);
  // A measurement step of +1: D = -Kp Td / (a Td) x (1 - e^(-h / (a Td))) x ... at once
  // (a = 0.2, Tf = 2 s, h = 0.1 s): D = a' x D + (1 - a') Kp Td (-1) / h.
  pid.Input = 51.0f;
  ctx.now += 100ms;
  pid(ctx);
  const double a = std::exp(-0.1 / 2.0);
  const double d1 = (1 - a) * 2.0 * 10.0 * (-1.0) / 0.1;
  EXPECT_NEAR(pid.DAction, d1, 1e-4);
  // Then it decays with the filter's time constant a Td = 2 s.
  ctx.now += 100ms;
  pid(ctx);
  EXPECT_NEAR(pid.DAction, a * d1, 1e-4);
  // With DWeighting = 1 the same setpoint step does kick.
  pc::PID_Compact kick = pid;
  kick.DWeighting = 1.0f;
  kick.Setpoint = 70.0f;
  ctx.now += 100ms;
  kick(ctx);
  EXPECT_GT(kick.DAction, 1.0f);
}

TEST(PidCompact, SetpointRampLimitsTheRate) {
  plc::ScanContext ctx{};
  ctx.period = 100ms;
  pc::PID_Compact pid;
  pid.SetpointRamp = 2.0f;  // K/s
  pid.Input = 20.0f;
  pid.Setpoint = 80.0f;
  pid(ctx);  // automatic begins: the ramp starts at the process value
  EXPECT_NEAR(pid.EffectiveSetpoint, 20.2f, 1e-4);
  for (int i = 0; i < 100; ++i) {
    ctx.now += 100ms;
    pid(ctx);
  }
  EXPECT_NEAR(pid.EffectiveSetpoint, 40.2f, 1e-3);  // 10 s later: 20 K more
  for (int i = 0; i < 300; ++i) {
    ctx.now += 100ms;
    pid(ctx);
  }
  EXPECT_FLOAT_EQ(pid.EffectiveSetpoint, 80.0f);  // and it stops at the setpoint
}

TEST(PidCompact, PwmOutputFollowsTheDuty) {
  plc::ScanContext ctx{};
  ctx.period = 10ms;
  pc::PID_Compact pid;
  pid.ManualEnable = true;
  pid.ManualValue = 30.0f;
  pid.PwmPeriod = 1s;
  int on = 0;
  for (int i = 0; i < 300; ++i, ctx.now += 10ms) {
    pid(ctx);
    on += pid.Output_PWM;
  }
  EXPECT_EQ(on, 90);  // 30 % of 3 s in 10 ms calls
  // A 0.5 % duty is 5 ms: below a 20 ms minimum on time it is dropped.
  pid.ManualValue = 0.5f;
  pid.MinimumOnTime = 20ms;
  on = 0;
  for (int i = 0; i < 300; ++i, ctx.now += 10ms) {
    pid(ctx);
    on += pid.Output_PWM;
  }
  EXPECT_EQ(on, 0);
  EXPECT_EQ(pid.Output_PER, 138);  // 0.5 % of 27648
}

TEST(PidCompact, AnalogInputScaling) {
  plc::ScanContext ctx{};
  ctx.period = 100ms;
  pc::PID_Compact pid;
  pid.InputPerOn = true;
  pid.InputScalingUpperOut = 300.0f;  // 0..27648 = 0..300 degC
  pid.InputUpperLimit = 350.0f;
  pid.Input_PER = 13824;
  pid.Setpoint = 150.0f;
  pid(ctx);
  EXPECT_FLOAT_EQ(pid.ScaledInput, 150.0f);
  EXPECT_FALSE(pid.Error);
  pid.Input_PER = 32767;  // overflow: a broken wire
  ctx.now += 100ms;
  pid(ctx);
  EXPECT_TRUE(pid.Error);
  EXPECT_EQ(std::uint32_t(pid.ErrorBits), pc::error_bits::kInputPerInvalid);
  EXPECT_EQ(pid.State, INT(pc::PID_Compact::Mode::Substitute));
}

TEST(PidCompact, ErrorReactionsAndRecovery) {
  plc::ScanContext ctx{};
  ctx.period = 100ms;
  pc::PID_Compact pid;
  pid.Gain = 1.0f;
  pid.Ti = 10.0f;
  pid.Setpoint = 50.0f;
  pid.Input = 40.0f;
  pid.SubstituteOutput = 25.0f;
  for (int i = 0; i < 10; ++i, ctx.now += 100ms) pid(ctx);
  EXPECT_EQ(pid.State, INT(pc::PID_Compact::Mode::Automatic));
  // 0200h: Input not a number -> substitute output (State 5).
  pid.Input = NAN;
  pid(ctx);
  ctx.now += 100ms;
  EXPECT_EQ(pid.State, INT(pc::PID_Compact::Mode::Substitute));
  EXPECT_EQ(pid.Output, 25.0f);
  EXPECT_EQ(std::uint32_t(pid.ErrorBits), pc::error_bits::kInputInvalid);
  // Valid again: automatic, bumpless from the substitute value; ErrorBits
  // stay latched until ErrorAck, Error only while the error is pending.
  pid.Input = 40.0f;
  pid(ctx);
  ctx.now += 100ms;
  EXPECT_EQ(pid.State, INT(pc::PID_Compact::Mode::Automatic));
  EXPECT_FLOAT_EQ(pid.Output, 25.0f);
  EXPECT_FALSE(pid.Error);
  EXPECT_EQ(std::uint32_t(pid.ErrorBits), pc::error_bits::kInputInvalid);
  pid.ErrorAck = true;
  pid(ctx);
  ctx.now += 100ms;
  EXPECT_EQ(std::uint32_t(pid.ErrorBits), 0u);
  // 0001h: outside the process value limits: automatic goes on (recover mode).
  pid.Input = 130.0f;
  pid(ctx);
  ctx.now += 100ms;
  EXPECT_EQ(pid.State, INT(pc::PID_Compact::Mode::Automatic));
  EXPECT_EQ(std::uint32_t(pid.ErrorBits), pc::error_bits::kInputOutOfLimits);
  // Without ActivateRecoverMode it goes inactive, output 0.
  pid.ActivateRecoverMode = false;
  pid(ctx);
  ctx.now += 100ms;
  EXPECT_EQ(pid.State, INT(pc::PID_Compact::Mode::Inactive));
  EXPECT_EQ(pid.Output, 0.0f);
  // 0100h: invalid parameters (limits the wrong way round).
  pid.ActivateRecoverMode = true;
  pid.Input = 40.0f;
  pid.OutputLowerLimit = 100.0f;
  pid(ctx);
  ctx.now += 100ms;
  EXPECT_NE(std::uint32_t(pid.ErrorBits) & pc::error_bits::kInvalidParameters, 0u);
  EXPECT_EQ(pid.State, INT(pc::PID_Compact::Mode::Substitute));
  // 0800h: called twice in one scan.
  pid.OutputLowerLimit = 0.0f;
  pid(ctx);
  pid(ctx);
  EXPECT_NE(std::uint32_t(pid.ErrorBits) & pc::error_bits::kSamplingTime, 0u);
  // Reset: inactive while TRUE, the latched bits cleared on its edge.
  pid.Reset = true;
  ctx.now += 100ms;
  pid(ctx);
  EXPECT_EQ(pid.State, INT(pc::PID_Compact::Mode::Inactive));
  EXPECT_EQ(std::uint32_t(pid.ErrorBits), 0u);
  EXPECT_EQ(pid.Output, 0.0f);
}

}  // namespace

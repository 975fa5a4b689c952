// CONT_C against its block diagram (Siemens A5E35300227, "CONT_C"): the P,
// I and D paths with GAIN on all three, the integration with CYCLE, the
// dead band, PV_PER normalisation, LMN limits with their flags and the held
// integral, manual tracking (bumpless), COM_RST, and a closed loop.
#include <gtest/gtest.h>

#include <cmath>

#include "loop_harness.hpp"
#include "plc/fb/control/cont_c.hpp"

namespace pc = plc::control;
using namespace control_test;
using plc::TIME;

namespace {

struct Fixture {
  pc::CONT_C c;
  plc::ScanContext ctx{};
  Fixture() {
    ctx.period = 100ms;
    c.CYCLE = 100ms;
    c.MAN_ON = false;
  }
  void call(int n = 1) {
    for (int i = 0; i < n; ++i) {
      c(ctx);
      ctx.now += ctx.period;
    }
  }
};

TEST(ContC, ProportionalAndIntegralWithCycle) {
  Fixture f;
  f.c.GAIN = 2.0f;
  f.c.TI = 10s;
  f.c.SP_INT = 50.0f;
  f.c.PV_IN = 40.0f;
  f.call();
  EXPECT_FLOAT_EQ(f.c.ER, 10.0f);
  EXPECT_FLOAT_EQ(f.c.LMN_P, 20.0f);
  // LMN_I grows by GAIN x ER x CYCLE / TI = 2 x 10 x 0.1 / 10 = 0.2 per call.
  EXPECT_NEAR(f.c.LMN_I, 0.2f, 1e-6);
  f.call(9);
  EXPECT_NEAR(f.c.LMN_I, 2.0f, 1e-5);
  EXPECT_NEAR(f.c.LMN, 22.0f, 1e-5);
  // The integration uses CYCLE, not the time between calls: a block
  // called every 100 ms with CYCLE = 1 s integrates ten times too fast, as
  // on an S7.
  Fixture g;
  g.c.GAIN = 2.0f;
  g.c.TI = 10s;
  g.c.CYCLE = 1s;
  g.c.SP_INT = 50.0f;
  g.c.PV_IN = 40.0f;
  g.call(10);
  EXPECT_NEAR(g.c.LMN_I, 20.0f, 1e-4);
  // CYCLE = T#0s (our extension) measures it instead.
  Fixture m;
  m.c.GAIN = 2.0f;
  m.c.TI = 10s;
  m.c.CYCLE = TIME(0);
  m.c.SP_INT = 50.0f;
  m.c.PV_IN = 40.0f;
  m.call(10);
  EXPECT_NEAR(m.c.LMN_I, 2.0f, 1e-5);
}

TEST(ContC, DeadBandIsShifted) {
  Fixture f;
  f.c.I_SEL = false;
  f.c.GAIN = 1.0f;
  f.c.DEADB_W = 2.0f;
  f.c.SP_INT = 50.0f;
  f.c.PV_IN = 49.0f;
  f.call();
  EXPECT_EQ(f.c.ER, 0.0f);
  f.c.PV_IN = 45.0f;
  f.call();
  EXPECT_FLOAT_EQ(f.c.ER, 3.0f);
  f.c.PV_IN = 56.0f;
  f.call();
  EXPECT_FLOAT_EQ(f.c.ER, -4.0f);
}

TEST(ContC, PeripheralProcessValueIsNormalised) {
  Fixture f;
  f.c.PVPER_ON = true;
  f.c.PV_PER = 13824;  // 50 %
  f.c.PV_FAC = 2.0f;
  f.c.PV_OFF = 10.0f;
  f.call();
  EXPECT_FLOAT_EQ(f.c.PV, 110.0f);
  f.c.PV_PER = static_cast<std::uint16_t>(-13824);  // -50 %: a WORD holding an INT
  f.call();
  EXPECT_FLOAT_EQ(f.c.PV, -90.0f);
}

TEST(ContC, LimitsFlagsAndHeldIntegral) {
  Fixture f;
  f.c.GAIN = 1.0f;
  f.c.TI = 1s;
  f.c.SP_INT = 100.0f;
  f.c.PV_IN = 0.0f;
  f.c.LMN_HLM = 80.0f;
  f.call(100);
  EXPECT_FLOAT_EQ(f.c.LMN, 80.0f);
  EXPECT_TRUE(f.c.QLMN_HLM);
  EXPECT_FALSE(f.c.QLMN_LLM);
  // The integral stopped once the output hit the limit: P = 100 is above
  // it from the start, so it never grew at all.
  EXPECT_EQ(f.c.LMN_I, 0.0f);
  f.c.LMN_FAC = 0.5f;
  f.c.LMN_OFF = 10.0f;
  f.call();
  EXPECT_FLOAT_EQ(f.c.LMN, 50.0f);  // 80 x 0.5 + 10
  EXPECT_EQ(std::uint16_t(f.c.LMN_PER), 13824);
  // Below the low limit, LMN_PER carries the negative value as a WORD.
  f.c.LMN_FAC = 1.0f;
  f.c.LMN_OFF = 0.0f;
  f.c.LMN_LLM = -20.0f;
  f.c.SP_INT = -100.0f;
  f.call();
  EXPECT_FLOAT_EQ(f.c.LMN, -20.0f);
  EXPECT_TRUE(f.c.QLMN_LLM);
  EXPECT_EQ(std::int16_t(std::uint16_t(f.c.LMN_PER)), -5530);
}

TEST(ContC, ManualTracksAndSwitchesBumplessly) {
  Fixture f;
  f.c.MAN_ON = true;
  f.c.MAN = 30.0f;
  f.c.GAIN = 2.0f;
  f.c.SP_INT = 50.0f;
  f.c.PV_IN = 45.0f;
  f.call(5);
  EXPECT_FLOAT_EQ(f.c.LMN, 30.0f);
  f.c.MAN_ON = false;
  f.call();
  // P = 10, I tracked 30 - 10 = 20, plus one step of integration 0.1.
  EXPECT_NEAR(f.c.LMN, 30.0f + 2.0f * 5.0f * 0.1f / 20.0f, 1e-5);
}

TEST(ContC, HoldInitialiseAndRestart) {
  Fixture f;
  f.c.GAIN = 1.0f;
  f.c.TI = 1s;
  f.c.SP_INT = 10.0f;
  f.call(10);
  const float i = f.c.LMN_I;
  EXPECT_GT(i, 0.0f);
  f.c.INT_HOLD = true;
  f.call(10);
  EXPECT_EQ(f.c.LMN_I, i);
  f.c.I_ITL_ON = true;
  f.c.I_ITLVAL = 42.0f;
  f.call();
  EXPECT_EQ(f.c.LMN_I, 42.0f);
  f.c.COM_RST = true;
  f.c.I_ITL_ON = false;
  f.call();
  EXPECT_EQ(f.c.LMN, 0.0f);
  EXPECT_EQ(f.c.LMN_I, 0.0f);
}

TEST(ContC, DerivativeWithLag) {
  // D alone on an error step of 1 (SP 0 -> 1): LMN_D = GAIN TD / TM_LAG
  // e^(-t / TM_LAG) in continuous time; the first call after the step
  // gives (1 - a) GAIN TD / CYCLE, a = e^(-CYCLE / TM_LAG), then decays by a.
  Fixture f;
  f.c.P_SEL = false;
  f.c.I_SEL = false;
  f.c.D_SEL = true;
  f.c.GAIN = 2.0f;
  f.c.TD = 4s;
  f.c.TM_LAG = 1s;
  f.call(3);
  f.c.SP_INT = 1.0f;
  f.call();
  const double a = std::exp(-0.1);
  EXPECT_NEAR(f.c.LMN_D, (1 - a) * 2.0 * 4.0 / 0.1, 1e-4);
  f.call();
  EXPECT_NEAR(f.c.LMN_D, a * (1 - a) * 2.0 * 4.0 / 0.1, 1e-4);
}

TEST(ContC, ClosedLoopOnTheOven) {
  // The oven of the PID_Compact tests in percent (PV = degC / 3), PI with
  // the same tuning in CONT_C's form (GAIN acts on the integral too).
  Loop l(fopdt(2.0 / 3.0, 60.0, 5s, 10ms), 100ms);
  pc::CONT_C c;
  c.MAN_ON = false;
  c.CYCLE = 100ms;
  c.GAIN = 3.0f;
  c.TI = 40s;
  c.SP_INT = 20.0f;
  l.run(900s, [&](const plc::ScanContext& ctx, double pv) {
    c.PV_IN = static_cast<plc::REAL>(pv);
    c(ctx);
    return double(c.LMN);
  });
  EXPECT_NEAR(l.pv(), 20.0, 0.01);
}

}  // namespace

// The tuning aid: FOPDT least squares recovering known parameters from
// noisy step responses (stated tolerances), the tuning rules' formulas
// (Skogestad 2003, Ziegler & Nichols 1942), and PID_StepTune running a step
// test on a plant, its error codes and abort.
#include <gtest/gtest.h>

#include <cmath>

#include "loop_harness.hpp"
#include "plc/fb/control/pid_step_tune.hpp"
#include "plc/fb/control/tuning_rules.hpp"
#include "plc/sim/seeded_noise.hpp"

namespace pc = plc::control;
using namespace control_test;
using plc::INT;
using plc::TIME;

namespace {

// The step response of K/(T s + 1) e^(-L s) to du, sampled every ts for n
// samples (t = 0 at the step), with gaussian noise of sigma.
std::vector<double> noisy_step(double K, double T, TIME L, double du, TIME ts, int n, double sigma,
                               std::uint64_t seed) {
  auto plant = fopdt(K, T, L, ts);
  plc::sim::SeededNoise noise(seed);
  std::vector<double> y;
  const double u[1] = {du};
  for (int j = 0; j < n; ++j) {
    y.push_back(plant.outputs()[0] + sigma * noise.gaussian());
    plant.step(u);
  }
  return y;
}

TEST(FopdtFit, NoiseFreeDataGivesTheModelBack) {
  const auto y = noisy_step(2.0, 30.0, 7s, 10.0, 100ms, 2000, 0.0, 1);
  const auto r = pc::FopdtFitter::fit(y, 0.1, 10.0);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.model.gain, 2.0, 1e-6);
  EXPECT_NEAR(r.model.time_constant, 30.0, 1e-4);
  EXPECT_NEAR(r.model.dead_time, 7.0, 1e-4);
  EXPECT_GT(r.fit_percent, 99.99);
}

TEST(FopdtFit, RecoversKnownParametersFromNoisyData) {
  // Stated tolerances: with noise of 1 % of the final deviation (sigma 0.2
  // on a 20-unit response) over 200 s sampled at 0.1 s, K within 1 %, T
  // within 3 %, L within 0.3 s, for each of 20 noise sequences; the fit
  // percentage is above 90 and the residual estimates the noise within 10 %.
  double worst_k = 0, worst_t = 0, worst_l = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const auto y = noisy_step(2.0, 30.0, 7s, 10.0, 100ms, 2000, 0.2, seed);
    const auto r = pc::FopdtFitter::fit(y, 0.1, 10.0);
    ASSERT_TRUE(r.ok) << "seed " << seed;
    worst_k = std::max(worst_k, std::fabs(r.model.gain / 2.0 - 1));
    worst_t = std::max(worst_t, std::fabs(r.model.time_constant / 30.0 - 1));
    worst_l = std::max(worst_l, std::fabs(r.model.dead_time - 7.0));
    EXPECT_GT(r.fit_percent, 90.0) << "seed " << seed;
    EXPECT_NEAR(r.noise_sigma, 0.2, 0.02) << "seed " << seed;
  }
  std::printf(
      "FOPDT from noisy data (20 seeds): |dK/K| <= %.3f %%, |dT/T| <= %.3f %%, |dL| <= %.3f s\n",
      100 * worst_k, 100 * worst_t, worst_l);
  EXPECT_LE(worst_k, 0.01);
  EXPECT_LE(worst_t, 0.03);
  EXPECT_LE(worst_l, 0.3);
}

TEST(FopdtFit, ApproximatesAHigherOrderPlant) {
  // Two lags, 20 s and 5 s: no FOPDT fits exactly; the fit still finds the
  // gain, a dead time that stands in for the small lag (Skogestad's half
  // rule would say T = 22.5 s, L = 2.5 s), and says the fit is imperfect.
  plc::plant::LinearPlant p(
      plc::plant::discretise_zoh(plc::plant::second_order(1.5, 20, 5), 100ms));
  std::vector<double> y;
  const double u[1] = {4.0};
  for (int j = 0; j < 2000; ++j) {
    y.push_back(p.outputs()[0]);
    p.step(u);
  }
  const auto r = pc::FopdtFitter::fit(y, 0.1, 4.0);
  ASSERT_TRUE(r.ok);
  std::printf("two lags as FOPDT: K %.4f T %.3f L %.3f fit %.2f %%\n", r.model.gain,
              r.model.time_constant, r.model.dead_time, r.fit_percent);
  EXPECT_NEAR(r.model.gain, 1.5, 0.01);
  EXPECT_NEAR(r.model.time_constant, 22.5, 2.5);
  EXPECT_NEAR(r.model.dead_time, 2.5, 1.5);
  EXPECT_GT(r.fit_percent, 90.0);
  EXPECT_LT(r.fit_percent, 99.9);
}

TEST(FopdtFit, RefusesDataWithoutAResponse) {
  std::vector<double> flat(100, 0.0);
  EXPECT_FALSE(pc::FopdtFitter::fit(flat, 0.1, 1.0).ok);
  std::vector<double> few{0, 1, 2};
  EXPECT_FALSE(pc::FopdtFitter::fit(few, 0.1, 1.0).ok);
}

TEST(TuningRules, FormulasOfThePapers) {
  const pc::FopdtModel m{2.0, 60.0, 5.0};
  // SIMC, tau_c = max(L, T / 10) = 6 (default): Kc = 60 / (2 x 11),
  // Ti = min(60, 44) = 44.
  auto g = pc::tune(pc::TuningRule::SIMC_PI, m);
  ASSERT_TRUE(g.ok);
  EXPECT_DOUBLE_EQ(g.gain, 60.0 / 22.0);
  EXPECT_DOUBLE_EQ(g.ti, 44.0);
  EXPECT_EQ(g.td, 0.0);
  // tau_c = L as the paper's "tight control": Kc = 60 / (2 x 10) = 3,
  // Ti = min(60, 40) = 40.
  g = pc::tune(pc::TuningRule::SIMC_PI, m, 5.0);
  EXPECT_DOUBLE_EQ(g.gain, 3.0);
  EXPECT_DOUBLE_EQ(g.ti, 40.0);
  // SIMC with tau_c = 20: Kc = 60 / (2 x 25) = 1.2, Ti = min(60, 100) = 60.
  g = pc::tune(pc::TuningRule::SIMC_PI, m, 20.0);
  EXPECT_DOUBLE_EQ(g.gain, 1.2);
  EXPECT_DOUBLE_EQ(g.ti, 60.0);
  // Ziegler-Nichols reaction curve, a = K L / T = 1/6.
  g = pc::tune(pc::TuningRule::ZN_PI, m);
  EXPECT_NEAR(g.gain, 5.4, 1e-12);
  EXPECT_NEAR(g.ti, 5.0 / 0.3, 1e-12);
  g = pc::tune(pc::TuningRule::ZN_PID, m);
  EXPECT_NEAR(g.gain, 7.2, 1e-12);
  EXPECT_DOUBLE_EQ(g.ti, 10.0);
  EXPECT_DOUBLE_EQ(g.td, 2.5);
  // ZN needs a dead time; SIMC without one uses tau_c = T / 10.
  EXPECT_FALSE(pc::tune(pc::TuningRule::ZN_PI, {2.0, 60.0, 0.0}).ok);
  g = pc::tune(pc::TuningRule::SIMC_PI, {2.0, 60.0, 0.0});
  EXPECT_DOUBLE_EQ(g.gain, 5.0);
}

// PID_StepTune driving the oven (2 degC/%, 60 s, 5 s dead time, 20 degC
// ambient, 0.05 degC measurement noise) every 100 ms.
struct TuneRun {
  // At rest at 10 %: 40 degC.
  Loop loop{fopdt(2.0, 60.0, 5s, 10ms, 10.0), 100ms};
  pc::PID_StepTune tune;
  plc::sim::SeededNoise noise{7};
  double sigma = 0.05;

  TuneRun() {
    loop.offset = 20.0;
    tune.BaseOutput = 10.0f;
    tune.StepSize = 20.0f;
    tune.SettleTime = 20s;
    tune.TestTime = 300s;
  }
  // Runs until the block is neither busy nor just started, at most `limit`.
  void run(TIME limit) {
    tune.Execute = true;
    loop.run(limit, [&](const plc::ScanContext& ctx, double pv) {
      tune.Input = static_cast<plc::REAL>(pv + sigma * noise.gaussian());
      if (tune.Done || tune.Error || tune.CommandAborted) return double(tune.Output);
      tune(ctx);
      return double(tune.Output);
    });
  }
};

TEST(PidStepTune, StepTestIdentifiesTheOvenAndProposesGains) {
  TuneRun r;
  r.run(400s);
  ASSERT_TRUE(r.tune.Done) << "ErrorID " << std::hex << std::uint16_t(r.tune.ErrorID);
  std::printf(
      "step test: K %.4f T %.3f L %.3f fit %.2f %% R2 %.5f sigma %.4f iterations %d -> "
      "Kc %.4f Ti %.3f\n",
      r.tune.ProcessGain, r.tune.TimeConstant, r.tune.DeadTime, r.tune.FitPercent, r.tune.RSquared,
      r.tune.NoiseSigma, int(r.tune.Iterations), r.tune.Gain, r.tune.Ti);
  // Stated tolerances: K within 1 %, T within 2 %, L within 0.3 s of the
  // plant's 5 s (the PLC's own exchange adds up to one call, 0.1 s).
  EXPECT_NEAR(r.tune.ProcessGain, 2.0, 0.02);
  EXPECT_NEAR(r.tune.TimeConstant, 60.0, 1.2);
  EXPECT_NEAR(r.tune.DeadTime, 5.05, 0.3);
  EXPECT_GT(r.tune.FitPercent, 95.0f);
  EXPECT_NEAR(r.tune.NoiseSigma, 0.05, 0.01);
  // The proposal is the SIMC rule applied to the identified model.
  const auto g =
      pc::tune(pc::TuningRule::SIMC_PI, {r.tune.ProcessGain, r.tune.TimeConstant, r.tune.DeadTime});
  EXPECT_NEAR(r.tune.Gain, g.gain, 1e-4);
  EXPECT_NEAR(r.tune.Ti, g.ti, 1e-3);
  EXPECT_EQ(r.tune.Output, 30.0f);  // still on the step: the program decides
}

TEST(PidStepTune, ErrorsAndAbort) {
  {
    TuneRun r;
    r.tune.StepSize = 0.0f;
    r.run(1s);
    EXPECT_TRUE(r.tune.Error);
    EXPECT_EQ(std::uint16_t(r.tune.ErrorID), 0x8001);
  }
  {
    // A plant that does not answer (gain 0.0001 degC/%): no response.
    TuneRun r;
    r.loop = Loop(fopdt(0.0001, 60.0, 5s, 10ms, 10.0), 100ms);
    r.loop.offset = 20.0;
    r.run(400s);
    EXPECT_TRUE(r.tune.Error);
    EXPECT_EQ(std::uint16_t(r.tune.ErrorID), 0x8003);
  }
  {
    TuneRun r;
    r.sigma = NAN;
    r.run(1s);
    EXPECT_EQ(std::uint16_t(r.tune.ErrorID), 0x8002);
  }
  {
    // Ziegler-Nichols on a plant without dead time.
    TuneRun r;
    r.loop = Loop(fopdt(2.0, 60.0, TIME(0), 10ms, 10.0), 10ms);
    r.loop.offset = 20.0;
    r.sigma = 0;
    r.tune.Rule = INT(pc::TuningRule::ZN_PID);
    r.run(400s);
    EXPECT_EQ(std::uint16_t(r.tune.ErrorID), 0x8005);
  }
  {
    TuneRun r;
    r.run(30s);
    ASSERT_TRUE(r.tune.Busy);
    EXPECT_EQ(r.tune.Output, 30.0f);
    r.tune.Abort = true;
    r.run(1s);
    EXPECT_TRUE(r.tune.CommandAborted);
    EXPECT_EQ(r.tune.Output, 10.0f);
  }
}

}  // namespace

// The plant core against closed-form step responses: exact ZOH
// discretisation (first order, two lags, oscillating second order, an
// integrator), dead time in whole and in fractional samples, the
// transfer-function realisation, refusals (sizes, instability, overflow)
// and a plant step that never allocates. The same matrices against scipy:
// tests/plant/scipy_reference.py.
#include <gtest/gtest.h>

#include <cmath>

#include "allocation_counter.hpp"
#include "plc/sim/plant/linear_plant.hpp"
#include "plc/sim/seeded_noise.hpp"

namespace pl = plc::plant;
using namespace std::chrono_literals;

namespace {

// Step response of `m` to u = `step` on every input, sampled every h, for
// `samples` samples: y[k] is the output at t = (k+1) h.
std::vector<double> step_response(const pl::ContinuousModel& m, plc::TIME h, int samples,
                                  double step = 1.0, std::vector<plc::TIME> dead = {}) {
  pl::DiscretiseOptions opt;
  opt.dead_time = std::move(dead);
  pl::LinearPlant p(pl::discretise_zoh(m, h, opt));
  std::vector<double> u(static_cast<std::size_t>(m.inputs()), step), y;
  for (int k = 0; k < samples; ++k) {
    p.step(u);
    y.push_back(p.outputs()[0]);
  }
  return y;
}

double t_of(int k, plc::TIME h) { return (k + 1) * std::chrono::duration<double>(h).count(); }

// The exact discretisation reproduces the continuous response at the
// sample instants up to rounding: 1e-12 of the final value over thousands
// of steps (rounding grows with the number of products).
constexpr double kExact = 1e-12;

TEST(PlantCore, FirstOrderStepIsExactAtTheSamples) {
  const double K = 2.0, T = 3.0;
  const auto y = step_response(pl::first_order(K, T), 1ms, 15000);
  for (int k = 0; k < 15000; k += 7)
    ASSERT_NEAR(y[k], K * (1 - std::exp(-t_of(k, 1ms) / T)), kExact * K) << "k=" << k;
}

TEST(PlantCore, FirstOrderStepDoesNotDependOnTheSampleTime) {
  // 1 ms, 10 ms and 250 ms samples land on the same curve at common instants.
  const double K = 1.5, T = 0.8;
  const auto a = step_response(pl::first_order(K, T), 1ms, 2000);
  const auto b = step_response(pl::first_order(K, T), 250ms, 8);
  for (int k = 0; k < 8; ++k) EXPECT_NEAR(b[k], a[(k + 1) * 250 - 1], kExact * K);
}

TEST(PlantCore, FirstOrderWithWholeSampleDeadTime) {
  const double K = 2.0, T = 3.0, L = 0.5;
  const auto y = step_response(pl::first_order(K, T), 1ms, 6000, 1.0, {500ms});
  for (int k = 0; k < 6000; ++k) {
    const double t = t_of(k, 1ms);
    const double want = t <= L ? 0.0 : K * (1 - std::exp(-(t - L) / T));
    ASSERT_NEAR(y[k], want, kExact * K) << "t=" << t;
  }
}

TEST(PlantCore, FirstOrderWithFractionalDeadTime) {
  // L = 0.5003 s on a 1 ms sample: 500 whole samples and 0.3 ms; the step
  // enters 0.7 ms before the end of the 501st sample, exactly.
  const double K = 2.0, T = 3.0, L = 0.5003;
  const auto y = step_response(pl::first_order(K, T), 1ms, 3000, 1.0, {500300us});
  for (int k = 0; k < 3000; ++k) {
    const double t = t_of(k, 1ms);
    const double want = t <= L ? 0.0 : K * (1 - std::exp(-(t - L) / T));
    ASSERT_NEAR(y[k], want, kExact * K) << "t=" << t;
  }
}

TEST(PlantCore, TwoLagsStepIsExact) {
  const double K = 0.7, T1 = 4.0, T2 = 1.5;
  const auto y = step_response(pl::second_order(K, T1, T2), 10ms, 3000);
  for (int k = 0; k < 3000; k += 3) {
    const double t = t_of(k, 10ms);
    const double want = K * (1 - (T1 * std::exp(-t / T1) - T2 * std::exp(-t / T2)) / (T1 - T2));
    ASSERT_NEAR(y[k], want, kExact * K) << "t=" << t;
  }
}

TEST(PlantCore, OscillatingSecondOrderWithDeadTimeIsExact) {
  const double K = 3.0, wn = 2.0, zeta = 0.3, L = 0.25;
  const double wd = wn * std::sqrt(1 - zeta * zeta);
  const auto y = step_response(pl::second_order_oscillating(K, wn, zeta), 1ms, 10000, 1.0, {250ms});
  for (int k = 0; k < 10000; k += 3) {
    const double t = t_of(k, 1ms) - L;
    const double want = t <= 0
                            ? 0.0
                            : K * (1 - std::exp(-zeta * wn * t) *
                                           (std::cos(wd * t) +
                                            zeta / std::sqrt(1 - zeta * zeta) * std::sin(wd * t)));
    ASSERT_NEAR(y[k], want, kExact * K) << "t=" << t;
  }
}

TEST(PlantCore, TransferFunctionRealisesTheSamePlant) {
  // num/den of 2 / (3 s + 1) and of the two lags give the shortcuts' responses.
  const auto a = step_response(pl::transfer_function({2.0}, {3.0, 1.0}), 1ms, 5000);
  const auto b = step_response(pl::first_order(2.0, 3.0), 1ms, 5000);
  for (int k = 0; k < 5000; ++k) ASSERT_NEAR(a[k], b[k], kExact);
  // (4 s + 1)(1.5 s + 1) = 6 s^2 + 5.5 s + 1
  const auto c = step_response(pl::transfer_function({0.7}, {6.0, 5.5, 1.0}), 10ms, 2000);
  const auto d = step_response(pl::second_order(0.7, 4.0, 1.5), 10ms, 2000);
  for (int k = 0; k < 2000; ++k) ASSERT_NEAR(c[k], d[k], 1e-11);
}

TEST(PlantCore, ProperTransferFunctionFeedsThrough) {
  // (s + 2) / (s + 1) = 1 + 1/(s + 1): y = 2 - e^(-t) for a unit step, and
  // the D term sees the input held up to the sample (linear_plant.hpp).
  const auto y = step_response(pl::transfer_function({1.0, 2.0}, {1.0, 1.0}), 1ms, 3000);
  for (int k = 0; k < 3000; k += 5) ASSERT_NEAR(y[k], 2 - std::exp(-t_of(k, 1ms)), kExact);
}

TEST(PlantCore, IntegratorIsAcceptedAndRamps) {
  // A tank's level: 1/s. Its eigenvalue 0 is not instability.
  const auto y = step_response(pl::transfer_function({0.5}, {1.0, 0.0}), 1ms, 4000);
  for (int k = 0; k < 4000; k += 11) ASSERT_NEAR(y[k], 0.5 * t_of(k, 1ms), 1e-12 * 4);
}

TEST(PlantCore, StateSpaceWithTwoInputsAndPerInputDeadTime) {
  // Two first-order channels summed: input 1 through 1/(s+1) with 20 ms
  // dead time, input 2 through 2/(0.5 s + 1) with 7.5 ms.
  const auto m = pl::state_space({{-1, 0}, {0, -2}}, {{1, 0}, {0, 4}}, {{1, 1}}, {});
  const auto y = step_response(m, 1ms, 3000, 1.0, {20ms, 7500us});
  for (int k = 0; k < 3000; ++k) {
    const double t = t_of(k, 1ms);
    const double a = t <= 0.02 ? 0 : 1 - std::exp(-(t - 0.02));
    const double b = t <= 0.0075 ? 0 : 2 * (1 - std::exp(-2 * (t - 0.0075)));
    ASSERT_NEAR(y[k], a + b, 1e-12 * 3) << "t=" << t;
  }
}

TEST(PlantCore, RefusesMatricesThatDoNotFit) {
  auto field_of = [](auto f) {
    try {
      f();
    } catch (const pl::PlantError& e) {
      return e.field + ": " + e.what();
    }
    return std::string("no error");
  };
  EXPECT_EQ(field_of([] { pl::state_space({{-1, 0}}, {{1}}, {{1}}, {}); }).substr(0, 2), "A:");
  EXPECT_EQ(field_of([] {
              pl::state_space({{-1, 0}, {0, -1}}, {{1}}, {{1, 0}}, {});
            }),
            "B: B is 1x1 but A is 2x2: B needs one row per state (2)");
  EXPECT_EQ(field_of([] {
              pl::state_space({{-1}}, {{1}}, {{1, 2}}, {});
            }),
            "C: C is 1x2 but A is 1x1: C needs one column per state (1)");
  EXPECT_EQ(field_of([] {
              pl::state_space({{-1}}, {{1, 1}}, {{1}}, {{0}});
            }),
            "D: D is 1x1, it must be 1x2 (one row per output as C, one column per input as B)");
  EXPECT_EQ(field_of([] {
              pl::state_space({{-1, 0}, {1}}, {{1}, {0}}, {{1, 0}}, {});
            }),
            "A: A row 2 has 1 entries, row 1 has 2 (every row needs the same number)");
  EXPECT_EQ(field_of([] {
              pl::state_space({{-1, NAN}, {0, 1}}, {{1}, {0}}, {{1, 0}}, {});
            }),
            "A: A(1,2) is not a finite number");
  EXPECT_EQ(field_of([] {
              pl::transfer_function({1, 0, 0}, {1, 1});
            }),
            "num: num is of degree 2, above den's 1: the plant is not proper (it differentiates)");
  EXPECT_EQ(field_of([] { pl::first_order(1, 0); }), "tau: tau must be a finite number above 0");
}

TEST(PlantCore, RefusesAnUnstablePlantUnlessAllowed) {
  const auto m = pl::state_space({{0.5}}, {{1}}, {{1}}, {});
  try {
    pl::discretise_zoh(m, 1ms);
    FAIL() << "an unstable plant was accepted";
  } catch (const pl::PlantError& e) {
    EXPECT_EQ(e.field, "A");
    EXPECT_NE(std::string(e.what()).find("unstable: A has an eigenvalue with real part 0.5"),
              std::string::npos)
        << e.what();
  }
  pl::DiscretiseOptions opt;
  opt.allow_unstable = true;
  const auto d = pl::discretise_zoh(m, 1ms, opt);
  EXPECT_NEAR(d.Phi(0, 0), std::exp(0.0005), 1e-15);
}

TEST(PlantCore, RefusesADiscretisationThatOverflows) {
  const auto m = pl::state_space({{800}}, {{1}}, {{1}}, {});
  pl::DiscretiseOptions opt;
  opt.allow_unstable = true;
  try {
    pl::discretise_zoh(m, 1s, opt);  // e^800 is beyond a double
    FAIL() << "a non-finite Phi was accepted";
  } catch (const pl::PlantError& e) {
    EXPECT_EQ(e.field, "A");
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
  }
}

TEST(PlantCore, StepsAllocateNothing) {
  if (!plant_test::counting()) GTEST_SKIP() << "a sanitizer owns malloc";
  // 20 states, 3 inputs with whole and fractional dead times.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(20, 20);
  for (int i = 0; i < 20; ++i) {
    A(i, i) = -1.0 - 0.1 * i;
    if (i) A(i, i - 1) = 0.5;
  }
  pl::Rows a(20, std::vector<double>(20)), b(20, std::vector<double>(3, 0.1)),
      c(2, std::vector<double>(20, 0.05));
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) a[i][j] = A(i, j);
  pl::DiscretiseOptions opt;
  opt.dead_time = {0ms, 30ms, 12300us};
  pl::LinearPlant p(pl::discretise_zoh(pl::state_space(a, b, c, {}), 1ms, opt));
  std::vector<double> u{1.0, 0.5, -0.25};
  const std::size_t before = plant_test::allocations();
  double sum = 0;
  for (int k = 0; k < 10000; ++k) {
    p.step(u);
    sum += p.outputs()[1];
  }
  EXPECT_EQ(plant_test::allocations(), before) << "the plant step allocated";
  EXPECT_TRUE(std::isfinite(sum));
}

// The one generator of the device models (plc/sim/seeded_noise.hpp), known
// answers taken from it when the PR5510's filling process and the plant
// core were checked number for number against each other: a change of any
// of them changes every recorded trace with noise (tests/golden).
TEST(PlantCore, SeededNoiseKnownAnswers) {
  plc::sim::SeededNoise a(42);
  EXPECT_EQ(a.next_u64(), 6255019084209693600ULL);
  plc::sim::SeededNoise g(42);
  EXPECT_EQ(g.gaussian(), 0x1.2f23475957b8fp-2);
  EXPECT_EQ(g.gaussian(), -0x1.70cc267b6ae49p+0);  // the pair's spare
  EXPECT_EQ(g.gaussian(), 0x1.49ebe917f603ap-1);
  plc::sim::SeededNoise u(42);
  EXPECT_EQ(u.uniform_pm1(), -0x1.498daa447323p-2);
  EXPECT_EQ(u.uniform_pm1(), 0x1.2107ad4faeecap-1);
  plc::sim::SeededNoise z(0);  // seed 0 would stay 0: the golden ratio instead
  EXPECT_EQ(z.next_u64(), 973819730272012410ULL);
  plc::sim::SeededNoise d(42);
  double sum = 0;
  for (int i = 0; i < 1000; ++i) sum += d.gaussian();
  EXPECT_EQ(sum, -0x1.2d30f0337cc2dp+5);
}

}  // namespace

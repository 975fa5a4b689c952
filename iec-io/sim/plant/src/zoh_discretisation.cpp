#include "plc/sim/plant/zoh_discretisation.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <unsupported/Eigen/MatrixFunctions>

namespace plc::plant {
namespace {

double seconds(TIME t) { return std::chrono::duration<double>(t).count(); }

// exp([[A, B], [0, 0]] t): [[e^(A t), ∫0..t e^(A s) ds B], [0, I]].
Eigen::MatrixXd augmented_exp(const ContinuousModel& m, double t) {
  const Eigen::Index n = m.A.rows(), k = m.B.cols();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n + k, n + k);
  M.topLeftCorner(n, n) = m.A * t;
  M.topRightCorner(n, k) = m.B * t;
  return M.exp();
}

std::string number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

}  // namespace

double max_real_eigenvalue(const Eigen::MatrixXd& A) {
  Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
  double r = -INFINITY;
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i)
    r = std::max(r, es.eigenvalues()[i].real());
  return r;
}

DiscreteModel discretise_zoh(const ContinuousModel& m, TIME h, const DiscretiseOptions& opt) {
  if (h <= TIME(0)) throw PlantError("sample", "the sample time must be above 0");
  const Eigen::Index n = m.A.rows(), k = m.B.cols();
  if (!opt.dead_time.empty() && static_cast<Eigen::Index>(opt.dead_time.size()) != k)
    throw PlantError("dead_time", "one dead time per input is needed (" + std::to_string(k) +
                                      "), got " + std::to_string(opt.dead_time.size()));
  // An eigenvalue at 0 (an integrator: a tank's level) comes out of the
  // solver as a few ulps either side; only a clear positive real part,
  // relative to the size of A, is instability.
  const double re = max_real_eigenvalue(m.A);
  const double tol = 1e-9 * (1.0 + m.A.cwiseAbs().maxCoeff());
  if (re > tol && !opt.allow_unstable) {
    throw PlantError("A", "the plant is unstable: A has an eigenvalue with real part " +
                              number(re) + " 1/s > 0 (the output grows as e^(" + number(re) +
                              " t) without input); check the signs of A, or set "
                              "allow_unstable: true if the plant really is unstable");
  }
  DiscreteModel d;
  d.h = h;
  const double hs = seconds(h);
  const Eigen::MatrixXd E = augmented_exp(m, hs);
  d.Phi = E.topLeftCorner(n, n);
  d.Gamma0 = E.topRightCorner(n, k);
  d.Gamma1 = Eigen::MatrixXd::Zero(n, k);
  d.C = m.C;
  d.D = m.D;
  d.delay_samples.assign(static_cast<std::size_t>(k), 0);
  d.delay_fraction.assign(static_cast<std::size_t>(k), TIME(0));
  for (Eigen::Index i = 0; i < k && !opt.dead_time.empty(); ++i) {
    const TIME L = opt.dead_time[static_cast<std::size_t>(i)];
    if (L < TIME(0)) throw PlantError("dead_time", "a dead time must be at least 0");
    d.delay_samples[static_cast<std::size_t>(i)] = L / h;
    const TIME tau = L % h;
    d.delay_fraction[static_cast<std::size_t>(i)] = tau;
    if (tau == TIME(0)) continue;
    const Eigen::MatrixXd E0 = augmented_exp(m, seconds(h - tau));
    const Eigen::MatrixXd E1 = augmented_exp(m, seconds(tau));
    d.Gamma0.col(i) = E0.topRightCorner(n, k).col(i);
    d.Gamma1.col(i) = E0.topLeftCorner(n, n) * E1.topRightCorner(n, k).col(i);
  }
  if (!d.Phi.allFinite() || !d.Gamma0.allFinite() || !d.Gamma1.allFinite())
    throw PlantError(
        "A", "the discretised plant is not finite (e^(A h) overflows for h = " + number(hs) +
                 " s): the plant is far too fast or unstable for this "
                 "sample time; choose a shorter sample or check A");
  return d;
}

}  // namespace plc::plant

#include "plc/sim/plant/continuous_model.hpp"

#include <cmath>

namespace plc::plant {
namespace {

std::string dims(Eigen::Index r, Eigen::Index c) {
  return std::to_string(r) + "x" + std::to_string(c);
}

Eigen::MatrixXd matrix(const std::string& field, const Rows& rows) {
  if (rows.empty() || rows.front().empty())
    throw PlantError(field, field + " is empty (give it as a list of rows, e.g. [[1, 0], [0, 1]])");
  const std::size_t cols = rows.front().size();
  Eigen::MatrixXd m(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (rows[r].size() != cols)
      throw PlantError(field, field + " row " + std::to_string(r + 1) + " has " +
                                  std::to_string(rows[r].size()) + " entries, row 1 has " +
                                  std::to_string(cols) + " (every row needs the same number)");
    for (std::size_t c = 0; c < cols; ++c) {
      if (!std::isfinite(rows[r][c]))
        throw PlantError(field, field + "(" + std::to_string(r + 1) + "," + std::to_string(c + 1) +
                                    ") is not a finite number");
      m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = rows[r][c];
    }
  }
  return m;
}

void check_limits(const ContinuousModel& m) {
  if (m.states() > kMaxStates)
    throw PlantError("A", "the plant has " + std::to_string(m.states()) + " states, at most " +
                              std::to_string(kMaxStates) + " are supported");
  if (m.inputs() > kMaxInputs)
    throw PlantError("B", "the plant has " + std::to_string(m.inputs()) +
                              " inputs (columns of B), at most " + std::to_string(kMaxInputs) +
                              " are supported");
  if (m.outputs() > kMaxOutputs)
    throw PlantError("C", "the plant has " + std::to_string(m.outputs()) +
                              " outputs (rows of C), at most " + std::to_string(kMaxOutputs) +
                              " are supported");
}

void positive(const char* field, double v) {
  if (!(v > 0) || !std::isfinite(v))
    throw PlantError(field, std::string(field) + " must be a finite number above 0");
}

void finite(const char* field, double v) {
  if (!std::isfinite(v)) throw PlantError(field, std::string(field) + " must be a finite number");
}

}  // namespace

ContinuousModel state_space(const Rows& A, const Rows& B, const Rows& C, const Rows& D) {
  ContinuousModel m;
  m.A = matrix("A", A);
  if (m.A.rows() != m.A.cols())
    throw PlantError(
        "A", "A is " + dims(m.A.rows(), m.A.cols()) + ", it must be square (n x n, n states)");
  m.B = matrix("B", B);
  if (m.B.rows() != m.A.rows())
    throw PlantError("B", "B is " + dims(m.B.rows(), m.B.cols()) + " but A is " +
                              dims(m.A.rows(), m.A.cols()) + ": B needs one row per state (" +
                              std::to_string(m.A.rows()) + ")");
  m.C = matrix("C", C);
  if (m.C.cols() != m.A.rows())
    throw PlantError("C", "C is " + dims(m.C.rows(), m.C.cols()) + " but A is " +
                              dims(m.A.rows(), m.A.cols()) + ": C needs one column per state (" +
                              std::to_string(m.A.rows()) + ")");
  if (D.empty()) {
    m.D = Eigen::MatrixXd::Zero(m.C.rows(), m.B.cols());
  } else {
    m.D = matrix("D", D);
    if (m.D.rows() != m.C.rows() || m.D.cols() != m.B.cols())
      throw PlantError("D", "D is " + dims(m.D.rows(), m.D.cols()) + ", it must be " +
                                dims(m.C.rows(), m.B.cols()) +
                                " (one row per output as C, one column per input as B)");
  }
  check_limits(m);
  return m;
}

ContinuousModel transfer_function(const std::vector<double>& num, const std::vector<double>& den) {
  for (double v : num) finite("num", v);
  for (double v : den) finite("den", v);
  // Leading zeros carry no degree: [0, 1, 2] is s + 2.
  std::size_t d0 = 0;
  while (d0 < den.size() && den[d0] == 0.0) ++d0;
  std::size_t n0 = 0;
  while (n0 < num.size() && num[n0] == 0.0) ++n0;
  if (d0 == den.size()) throw PlantError("den", "den has no coefficient other than 0");
  const std::size_t n = den.size() - d0 - 1;  // order
  if (n == 0)
    throw PlantError("den", "den is a constant: the plant has no dynamics (give at least [T, 1])");
  if (n > static_cast<std::size_t>(kMaxStates))
    throw PlantError("den", "den is of order " + std::to_string(n) + ", at most " +
                                std::to_string(kMaxStates) + " is supported");
  if (n0 == num.size()) throw PlantError("num", "num is zero: the plant would never move");
  const std::size_t num_degree = num.size() - n0 - 1;
  if (num_degree > n)
    throw PlantError("num", "num is of degree " + std::to_string(num_degree) + ", above den's " +
                                std::to_string(n) +
                                ": the plant is not proper (it differentiates)");
  // Monic denominator s^n + a(n-1) s^(n-1) + .. + a0; numerator padded to
  // n+1 coefficients bn .. b0.
  const double lead = den[d0];
  std::vector<double> a(n), b(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) a[i] = den[den.size() - 1 - i] / lead;  // a[i]: s^i
  for (std::size_t i = 0; i <= num_degree; ++i) b[i] = num[num.size() - 1 - i] / lead;
  const auto N = static_cast<Eigen::Index>(n);
  ContinuousModel m;
  m.A = Eigen::MatrixXd::Zero(N, N);
  for (Eigen::Index i = 0; i + 1 < N; ++i) m.A(i, i + 1) = 1.0;
  for (Eigen::Index i = 0; i < N; ++i) m.A(N - 1, i) = -a[static_cast<std::size_t>(i)];
  m.B = Eigen::MatrixXd::Zero(N, 1);
  m.B(N - 1, 0) = 1.0;
  m.C = Eigen::MatrixXd(1, N);
  const double bn = b[n];
  for (Eigen::Index i = 0; i < N; ++i)
    m.C(0, i) = b[static_cast<std::size_t>(i)] - a[static_cast<std::size_t>(i)] * bn;
  m.D = Eigen::MatrixXd::Constant(1, 1, bn);
  return m;
}

ContinuousModel first_order(double gain, double tau) {
  finite("gain", gain);
  positive("tau", tau);
  ContinuousModel m;
  m.A = Eigen::MatrixXd::Constant(1, 1, -1.0 / tau);
  m.B = Eigen::MatrixXd::Constant(1, 1, gain / tau);
  m.C = Eigen::MatrixXd::Constant(1, 1, 1.0);
  m.D = Eigen::MatrixXd::Zero(1, 1);
  return m;
}

ContinuousModel second_order(double gain, double tau1, double tau2) {
  finite("gain", gain);
  positive("tau", tau1);
  positive("tau2", tau2);
  // x1 = output of K/(T1 s + 1), x2 = output of 1/(T2 s + 1) fed by x1.
  ContinuousModel m;
  m.A = Eigen::MatrixXd(2, 2);
  m.A << -1.0 / tau1, 0.0, 1.0 / tau2, -1.0 / tau2;
  m.B = Eigen::MatrixXd(2, 1);
  m.B << gain / tau1, 0.0;
  m.C = Eigen::MatrixXd(1, 2);
  m.C << 0.0, 1.0;
  m.D = Eigen::MatrixXd::Zero(1, 1);
  return m;
}

ContinuousModel second_order_oscillating(double gain, double wn, double zeta) {
  finite("gain", gain);
  positive("wn", wn);
  finite("zeta", zeta);
  if (zeta < 0) throw PlantError("zeta", "zeta must be at least 0 (below 0 the plant is unstable)");
  ContinuousModel m;
  m.A = Eigen::MatrixXd(2, 2);
  m.A << 0.0, 1.0, -wn * wn, -2.0 * zeta * wn;
  m.B = Eigen::MatrixXd(2, 1);
  m.B << 0.0, gain * wn * wn;
  m.C = Eigen::MatrixXd(1, 2);
  m.C << 1.0, 0.0;
  m.D = Eigen::MatrixXd::Zero(1, 1);
  return m;
}

}  // namespace plc::plant

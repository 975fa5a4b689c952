#include "plc/fb/control/fopdt_fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace plc::control {
namespace {

constexpr double kMinTimeConstantFraction = 1e-6;  // of the record's length

}  // namespace

double FopdtFitter::response(const FopdtModel& m, double du, double t) {
  if (t <= m.dead_time) return 0.0;
  return m.gain * du * (1.0 - std::exp(-(t - m.dead_time) / m.time_constant));
}

double FopdtFitter::sse(const double p[3]) const {
  const FopdtModel m{p[0], p[1], p[2]};
  double s = 0;
  for (std::size_t j = 0; j < y_.size(); ++j) {
    const double r = y_[j] - response(m, du_, static_cast<double>(j) * ts_);
    s += r * r;
  }
  return s;
}

bool FopdtFitter::start(std::span<const double> y, double ts, double du) {
  y_ = y;
  ts_ = ts;
  du_ = du;
  iterations_ = 0;
  lambda_ = 1e-3;
  done_ = true;
  valid_ = false;
  if (y.size() < 10 || !(ts > 0) || !(du != 0) || !std::isfinite(du)) return false;
  double sum = 0;
  for (double v : y) {
    if (!std::isfinite(v)) return false;
    sum += v;
  }
  mean_ = sum / static_cast<double>(y.size());
  sst_ = 0;
  for (double v : y) sst_ += (v - mean_) * (v - mean_);
  if (!(sst_ > 0)) return false;  // a flat record: no response to fit
  initial_estimate();
  if (!std::isfinite(p_[0]) || !(p_[1] > 0) || !(p_[2] >= 0)) return false;
  sse_ = sse(p_);
  done_ = false;
  valid_ = true;
  return true;
}

void FopdtFitter::initial_estimate() {
  const std::size_t n = y_.size();
  const double span = static_cast<double>(n - 1) * ts_;
  // Final value: the mean of the last tenth.
  const std::size_t tail = std::max<std::size_t>(1, n / 10);
  double y_end = 0;
  for (std::size_t j = n - tail; j < n; ++j) y_end += y_[j];
  y_end /= static_cast<double>(tail);

  // 1. The integral equation over the samples past half the final value.
  std::size_t j0 = n;
  for (std::size_t j = 0; j < n; ++j)
    if (std::fabs(y_[j]) > 0.5 * std::fabs(y_end)) {
      j0 = j;
      break;
    }
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  double area = 0;
  for (std::size_t j = 1; j < n; ++j) {
    area += 0.5 * (y_[j] + y_[j - 1]) * ts_;
    if (j < j0) continue;
    const Eigen::Vector3d phi(du_ * static_cast<double>(j) * ts_, -du_, -y_[j]);
    ata.noalias() += phi * phi.transpose();
    atb.noalias() += phi * area;
  }
  const Eigen::Vector3d theta = ata.ldlt().solve(atb);
  const double k = theta[0];
  const double l = k != 0 ? theta[1] / k : -1;
  const double t = theta[2];
  if (std::isfinite(k) && std::isfinite(l) && std::isfinite(t) && t > 0 && l >= 0 && l < span) {
    p_[0] = k;
    p_[1] = t;
    p_[2] = l;
    return;
  }
  // 2. Two points: 28.3 % at L + T/3, 63.2 % at L + T.
  auto crossing = [&](double fraction) {
    for (std::size_t j = 0; j < n; ++j)
      if (std::fabs(y_[j]) >= fraction * std::fabs(y_end)) return static_cast<double>(j) * ts_;
    return span;
  };
  const double t28 = crossing(0.283), t63 = crossing(0.632);
  p_[0] = y_end / du_;
  p_[1] = std::max(1.5 * (t63 - t28), kMinTimeConstantFraction * span + ts_);
  p_[2] = std::max(0.0, t63 - p_[1]);
}

bool FopdtFitter::iterate() {
  if (done_) return true;
  ++iterations_;
  // Jacobian of the model response in (K, T, L), and the residuals.
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
  Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
  const double K = p_[0], T = p_[1], L = p_[2];
  for (std::size_t j = 0; j < y_.size(); ++j) {
    const double t = static_cast<double>(j) * ts_;
    double f = 0;
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    if (t > L) {
      const double s = t - L;
      const double e = std::exp(-s / T);
      f = K * du_ * (1 - e);
      g << du_ * (1 - e), -K * du_ * e * s / (T * T), -K * du_ * e / T;
    }
    const double r = y_[j] - f;
    jtj.noalias() += g * g.transpose();
    jtr.noalias() += g * r;
  }
  Eigen::Matrix3d a = jtj;
  for (int i = 0; i < 3; ++i) a(i, i) += lambda_ * std::max(jtj(i, i), 1e-12);
  const Eigen::Vector3d delta = a.ldlt().solve(jtr);
  const double span = static_cast<double>(y_.size() - 1) * ts_;
  double trial[3] = {K + delta[0], std::max(T + delta[1], kMinTimeConstantFraction * span),
                     std::clamp(L + delta[2], 0.0, span)};
  const double s_trial = delta.allFinite() ? sse(trial) : INFINITY;
  if (s_trial < sse_) {
    const double rel_step = std::fabs(delta[0]) / (std::fabs(K) + 1e-300) +
                            std::fabs(delta[1]) / T + std::fabs(delta[2]) / (L + T);
    const double rel_sse = (sse_ - s_trial) / (sse_ + 1e-300);
    std::copy(trial, trial + 3, p_);
    sse_ = s_trial;
    lambda_ = std::max(lambda_ * 0.1, 1e-12);
    if (rel_step < 1e-9 || rel_sse < 1e-14) done_ = true;
  } else {
    lambda_ *= 10;
    if (lambda_ > 1e12) done_ = true;  // no step improves: at the minimum
  }
  if (iterations_ >= kMaxIterations) done_ = true;
  return done_;
}

FopdtResult FopdtFitter::result() const {
  FopdtResult r;
  r.model = {p_[0], p_[1], p_[2]};
  r.iterations = iterations_;
  r.ok = valid_ && std::isfinite(p_[0]) && std::isfinite(p_[1]) && std::isfinite(p_[2]) &&
         p_[1] > 0 && p_[2] >= 0 && std::isfinite(sse_);
  if (!valid_) return r;
  r.r_squared = 1 - sse_ / sst_;
  r.fit_percent = 100.0 * (1 - std::sqrt(sse_ / sst_));
  const double dof = std::max<double>(1.0, static_cast<double>(y_.size()) - 3.0);
  r.noise_sigma = std::sqrt(sse_ / dof);
  return r;
}

FopdtResult FopdtFitter::fit(std::span<const double> y, double ts, double du) {
  FopdtFitter f;
  if (!f.start(y, ts, du)) return f.result();
  for (int i = 0; i < kMaxIterations + 1 && !f.iterate(); ++i) {
  }
  return f.result();
}

}  // namespace plc::control

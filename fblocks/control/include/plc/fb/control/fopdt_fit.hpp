// Identification of a first-order-plus-dead-time model from a step test,
//
//   y(t) = K du (1 - e^(-(t - L) / T))  for t > L,  0 before,
//
// where y is the process value's deviation from its steady state before
// the step, du the step of the manipulated value, sampled at t = j ts
// (j = 0 .. n-1, t = 0 at the step). Least squares on Eigen, in two parts:
//
// 1. A start from the integral equation (no iteration): integrating
//    T dy/dt + y = K du 1(t - L) from 0 gives, for t >= L,
//      A(t) = K du t - K du L - T y(t),     A(t) = ∫0..t y,
//    linear in (K, K L, T): a 3x3 least-squares problem over the samples
//    after the response is under way (|y| above half its final value, so
//    surely t > L). Integrating first averages the noise out (Bi, Cai et
//    al., "Robust identification of first-order plus dead-time model from
//    step response", Control Eng. Practice 7, 1999). If that start is not
//    physical (T or L negative), the two-point start: K from the final
//    value, L and T from the 28 % and 63 % crossings (Smith 1972).
// 2. Levenberg-Marquardt on the output error sum_j (y_j - y(t_j))^2 in
//    (K, T, L), one iteration per iterate() call (each is two passes over
//    the samples, so a PLC block can spread the fit over scans and keep
//    each scan short), until the step is below 1e-9 of the parameters or
//    after kMaxIterations.
//
// Fit quality: FitPercent = 100 (1 - |y - y_model| / |y - mean(y)|) (the
// normalised RMSE fit MATLAB's `compare` reports), R^2 = 1 - SSE / SST, and
// the residual's standard deviation (an estimate of the noise).
//
// Nothing allocates (fixed-size Eigen 3x3 matrices; the samples stay the
// caller's).
#pragma once

#include <span>

namespace plc::control {

struct FopdtModel {
  double gain = 0;           // K: process units per output unit
  double time_constant = 0;  // T, s
  double dead_time = 0;      // L, s
};

struct FopdtResult {
  FopdtModel model;
  double fit_percent = 0;
  double r_squared = 0;
  double noise_sigma = 0;
  int iterations = 0;
  bool ok = false;  // a finite model with T > 0 and L >= 0
};

class FopdtFitter {
 public:
  static constexpr int kMaxIterations = 100;

  // Starts a fit over `y` (deviations, at least 10 samples) with sample
  // time ts > 0 (s) and step du != 0. The span must stay valid until done.
  // False when the data cannot give a model (too few samples, no response).
  bool start(std::span<const double> y, double ts, double du);
  // One Levenberg-Marquardt iteration; true when the fit is finished.
  bool iterate();
  [[nodiscard]] bool finished() const { return done_; }
  [[nodiscard]] FopdtResult result() const;

  // start() and iterate() to the end.
  static FopdtResult fit(std::span<const double> y, double ts, double du);

  // The model's response at t for a step du.
  static double response(const FopdtModel& m, double du, double t);

 private:
  double sse(const double p[3]) const;
  void initial_estimate();

  std::span<const double> y_;
  double ts_ = 0, du_ = 0;
  double p_[3] = {0, 0, 0};  // K, T, L
  double sse_ = 0, sst_ = 0, mean_ = 0;
  double lambda_ = 1e-3;
  int iterations_ = 0;
  bool done_ = true;
  bool valid_ = false;
};

}  // namespace plc::control

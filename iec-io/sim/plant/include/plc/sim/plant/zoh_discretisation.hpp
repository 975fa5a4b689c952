// Exact discretisation of a continuous plant for a zero-order-hold input
// (the input is constant between samples, as a PLC output is between
// scans), with a dead time per input.
//
// Without dead time (Åström & Wittenmark, Computer-Controlled Systems,
// 3rd ed., ch. 2.3):
//   x[k+1] = Phi x[k] + Gamma u[k],  Phi = e^(A h),  Gamma = ∫0..h e^(A s) ds B,
// both read from one matrix exponential of the augmented matrix
//   exp([[A, B], [0, 0]] h) = [[Phi, Gamma], [0, I]]
// (Van Loan 1978), computed by Eigen's MatrixFunctions (Padé approximant
// with scaling and squaring, Higham 2005), the method scipy's
// cont2discrete(method='zoh') uses too.
//
// With an input dead time L = d h + tau (0 <= tau < h) the input seen by the
// plant over the sample interval [k h, (k+1) h) is u[k-d-1] for the first
// tau and u[k-d] for the rest, so (ibid. ch. 2.6)
//   x[k+1] = Phi x[k] + Gamma0 u[k-d] + Gamma1 u[k-d-1],
//   Gamma0 = ∫0..(h-tau) e^(A s) ds B,
//   Gamma1 = e^(A (h-tau)) ∫0..tau e^(A s) ds B,
// column by column, since each input has its own dead time. Exact for any
// dead time, not only whole samples; tau = 0 gives Gamma1 = 0.
//
// h and the dead times are TIME (integer nanoseconds), so d and tau come out
// exactly (3 ms / 1 ms is 3, not 2.9999999).
#pragma once

#include <vector>

#include "plc/sim/plant/continuous_model.hpp"
#include "plc/types.hpp"

namespace plc::plant {

struct DiscreteModel {
  TIME h{};
  Eigen::MatrixXd Phi, Gamma0, Gamma1, C, D;
  std::vector<std::int64_t> delay_samples;  // d per input
  std::vector<TIME> delay_fraction;         // tau per input
};

struct DiscretiseOptions {
  // Dead time per input (empty: none; else one per input, each >= 0).
  std::vector<TIME> dead_time;
  // An unstable plant (an eigenvalue of A with a positive real part) is
  // usually a sign error in A; refused unless this is set.
  bool allow_unstable = false;
};

// Throws PlantError: field "A" for an unstable plant (naming the
// eigenvalue) and for matrices the exponential cannot represent (entries of
// A h so large that Phi or Gamma overflow: "sample" is then the remedy),
// "sample" for h <= 0, "dead_time" for a negative one.
DiscreteModel discretise_zoh(const ContinuousModel& m, TIME h, const DiscretiseOptions& opt = {});

// The largest real part of A's eigenvalues (the plant's slowest mode;
// > 0: unstable, 0: an integrator).
double max_real_eigenvalue(const Eigen::MatrixXd& A);

}  // namespace plc::plant

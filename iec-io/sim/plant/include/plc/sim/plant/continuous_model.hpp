// A linear time-invariant plant in continuous time,
//
//   dx/dt = A x + B u,   y = C x + D u,
//
// with n states, m inputs and p outputs, and the transfer-function forms
// engineers write first (first and second order lags, an oscillating second
// order, a numerator/denominator pair), each turned into state space here.
// Construction checks sizes and finiteness and says which matrix or
// coefficient is wrong (PlantError::field); nothing here runs in a scan.
//
// The sizes have fixed upper bounds (kMaxStates, kMaxInputs, kMaxOutputs) so
// that the discrete plant (linear_plant.hpp) keeps its matrices in storage
// of fixed size inside the object: a plant step never touches the heap.
#pragma once

#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <vector>

namespace plc::plant {

inline constexpr int kMaxStates = 32;
inline constexpr int kMaxInputs = 8;
inline constexpr int kMaxOutputs = 8;

// A plant description that cannot be simulated: `field` names the matrix,
// coefficient list or parameter ("A", "den", "tau", ...), the message says
// what is wrong with it in terms of the plant.
struct PlantError : std::runtime_error {
  PlantError(std::string field_, const std::string& msg)
      : std::runtime_error(msg), field(std::move(field_)) {}
  std::string field;
};

struct ContinuousModel {
  Eigen::MatrixXd A, B, C, D;  // n x n, n x m, p x n, p x m

  [[nodiscard]] int states() const { return static_cast<int>(A.rows()); }
  [[nodiscard]] int inputs() const { return static_cast<int>(B.cols()); }
  [[nodiscard]] int outputs() const { return static_cast<int>(C.rows()); }
};

// A row-major list of rows, as a config gives a matrix.
using Rows = std::vector<std::vector<double>>;

// State space from its four matrices. D may be empty (then zero). Throws
// PlantError naming the first matrix whose size does not fit A (B must have
// n rows, C n columns, D p x m), a ragged or empty one, a non-finite entry,
// or sizes beyond the limits above.
ContinuousModel state_space(const Rows& A, const Rows& B, const Rows& C, const Rows& D);

// G(s) = num(s) / den(s), coefficients from the highest power of s down
// (as in MATLAB and scipy: den = [T, 1] is T s + 1). Proper (numerator
// degree at most the denominator's), leading denominator coefficient not
// zero, order 1..kMaxStates. Realised in controllable canonical form:
//   A = [0 1 0 ..; ..; -a0 -a1 .. -a(n-1)], B = [0 .. 0 1]',
//   C = [b0 - a0 bn, .., b(n-1) - a(n-1) bn], D = bn
// after dividing by the leading denominator coefficient (the states are
// the output of 1/den(s) and its derivatives). Fields: "num", "den".
ContinuousModel transfer_function(const std::vector<double>& num, const std::vector<double>& den);

// K / (T s + 1). T > 0. Fields "gain", "tau".
ContinuousModel first_order(double gain, double tau);
// K / ((T1 s + 1)(T2 s + 1)), two real lags in series, as two states with
// the physical meaning "output of the first lag" and "output". T1, T2 > 0.
ContinuousModel second_order(double gain, double tau1, double tau2);
// K wn^2 / (s^2 + 2 zeta wn s + wn^2). wn > 0, zeta >= 0 (zeta < 1
// oscillates). States: y and dy/dt.
ContinuousModel second_order_oscillating(double gain, double wn, double zeta);

}  // namespace plc::plant

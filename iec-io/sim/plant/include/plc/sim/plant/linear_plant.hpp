// A discretised plant that runs: state, dead-time buffer and one step()
// per sample,
//
//   (u[k-d], u[k-d-1]) = dead-time buffer after storing u[k]
//   x[k+1] = Phi x[k] + Gamma0 u[k-d] + Gamma1 u[k-d-1]
//   y[k+1] = C x[k+1] + D u[k-d]
//
// y is the output at the end of the sample, read before the next input
// applies: the D term uses the input that was held up to that instant (a
// PLC reads its inputs before it writes new outputs).
//
// The matrices live in Eigen matrices of fixed maximum size (kMaxStates x
// kMaxStates, ...) inside the object, and the products are written with
// noalias(), so step() does no heap allocation and no exception; its cost
// grows with n^2 (tests/bench/bench_plant.cpp measures it for 1..20 states).
#pragma once

#include <span>

#include "plc/sim/plant/dead_time_line.hpp"
#include "plc/sim/plant/zoh_discretisation.hpp"

namespace plc::plant {

class LinearPlant {
 public:
  template <int R, int C>
  using Mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, R, C>;
  template <int R>
  using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, R, 1>;

  // Zero state; the dead-time buffer holds `initial_input` (empty: zeros).
  // Throws PlantError("dead_time") for a dead time beyond kMaxDelaySamples.
  explicit LinearPlant(const DiscreteModel& d, std::span<const double> initial_input = {});

  // Sets the state (size n) and recomputes the outputs. Config time.
  void set_state(std::span<const double> x);

  // One sample: `u` (m inputs) holds from now for one sample time h.
  void step(std::span<const double> u) {
    for (Eigen::Index i = 0; i < m_; ++i) u_[i] = u[static_cast<std::size_t>(i)];
    line_.push({u_.data(), static_cast<std::size_t>(m_)},
               {ud0_.data(), static_cast<std::size_t>(m_)},
               {ud1_.data(), static_cast<std::size_t>(m_)});
    next_.noalias() = phi_ * x_;
    next_.noalias() += gamma0_ * ud0_;
    if (fractional_) next_.noalias() += gamma1_ * ud1_;
    x_ = next_;
    y_.noalias() = c_ * x_;
    y_.noalias() += d_ * ud0_;
  }

  [[nodiscard]] std::span<const double> outputs() const {
    return {y_.data(), static_cast<std::size_t>(p_)};
  }
  [[nodiscard]] std::span<const double> state() const {
    return {x_.data(), static_cast<std::size_t>(n_)};
  }
  [[nodiscard]] int states() const { return static_cast<int>(n_); }
  [[nodiscard]] int inputs() const { return static_cast<int>(m_); }
  [[nodiscard]] int outputs_count() const { return static_cast<int>(p_); }
  [[nodiscard]] TIME sample() const { return h_; }

 private:
  Eigen::Index n_, m_, p_;
  TIME h_;
  bool fractional_ = false;  // some input has a dead time that is not whole samples
  Mat<kMaxStates, kMaxStates> phi_;
  Mat<kMaxStates, kMaxInputs> gamma0_, gamma1_;
  Mat<kMaxOutputs, kMaxStates> c_;
  Mat<kMaxOutputs, kMaxInputs> d_;
  Vec<kMaxStates> x_, next_;
  Vec<kMaxInputs> u_, ud0_, ud1_;
  Vec<kMaxOutputs> y_;
  DeadTimeLine line_;
};

}  // namespace plc::plant

#include "plc/sim/plant/linear_plant.hpp"

#include <vector>

namespace plc::plant {
namespace {

std::vector<std::int64_t> checked_delays(const DiscreteModel& d) {
  for (std::int64_t s : d.delay_samples)
    if (s > kMaxDelaySamples)
      throw PlantError("dead_time", "a dead time of " + std::to_string(s) + " samples: at most " +
                                        std::to_string(kMaxDelaySamples) +
                                        " (choose a longer sample time or a shorter dead time)");
  std::vector<std::int64_t> v = d.delay_samples;
  v.resize(static_cast<std::size_t>(d.Gamma0.cols()), 0);
  return v;
}

}  // namespace

LinearPlant::LinearPlant(const DiscreteModel& d, std::span<const double> initial_input)
    : n_(d.Phi.rows()), m_(d.Gamma0.cols()), p_(d.C.rows()), h_(d.h) {
  if (n_ > kMaxStates || m_ > kMaxInputs || p_ > kMaxOutputs)
    throw PlantError("A", "the plant is larger than supported (states, inputs, outputs)");
  const std::vector<std::int64_t> delays = checked_delays(d);
  std::vector<double> u0(static_cast<std::size_t>(m_), 0.0);
  for (std::size_t i = 0; i < initial_input.size() && i < u0.size(); ++i) u0[i] = initial_input[i];
  line_ = DeadTimeLine(delays, u0);
  phi_ = d.Phi;
  gamma0_ = d.Gamma0;
  gamma1_ = d.Gamma1;
  fractional_ = !d.Gamma1.isZero(0.0);
  c_ = d.C;
  d_ = d.D;
  x_ = Vec<kMaxStates>::Zero(n_);
  next_ = Vec<kMaxStates>::Zero(n_);
  u_ = Vec<kMaxInputs>::Zero(m_);
  ud0_ = Vec<kMaxInputs>::Zero(m_);
  ud1_ = Vec<kMaxInputs>::Zero(m_);
  for (Eigen::Index i = 0; i < m_; ++i) ud0_[i] = u0[static_cast<std::size_t>(i)];
  y_ = Vec<kMaxOutputs>::Zero(p_);
  y_.noalias() = c_ * x_;
  y_.noalias() += d_ * ud0_;
}

void LinearPlant::set_state(std::span<const double> x) {
  for (Eigen::Index i = 0; i < n_; ++i)
    x_[i] = static_cast<std::size_t>(i) < x.size() ? x[static_cast<std::size_t>(i)] : 0.0;
  y_.noalias() = c_ * x_;
  y_.noalias() += d_ * ud0_;
}

}  // namespace plc::plant

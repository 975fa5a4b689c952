#include "pr5510/filling_process.hpp"

#include <algorithm>
#include <cmath>

namespace plc::sim {

FillingProcess::FillingProcess(const FillingConfig& c)
    : cfg_(c),
      noise_(c.seed),
      flight_(static_cast<std::size_t>(std::max(0.0, c.fall_time_s) * 1000.0 + 0.5) + 1, 0.0),
      load_(c.initial_load),
      valve_step_(c.valve_time_s > 0.0 ? std::min(1.0, 0.001 / c.valve_time_s) : 1.0) {}

void FillingProcess::move(Valve& v, bool cmd) {
  if (cmd && !v.cmd) v.factor = 1.0 + cfg_.flow_variation * noise_.uniform_pm1();
  v.cmd = cmd;
  if (cmd) v.factor *= 1.0 + cfg_.flow_wander * 0.0316227766 * noise_.uniform_pm1();
  const double target = cmd ? 1.0 : 0.0;
  if (cfg_.valve_time_s <= 0.0) {
    v.open = target;
  } else {
    v.open += (target - v.open) * valve_step_;
    if (!cmd && v.open < 1e-4) v.open = 0.0;
  }
}

// A closed valve that stays closed: nothing moves (most steps, for most
// valves), and no noise is drawn.
void FillingProcess::drive(Valve& v, bool cmd) {
  if (!cmd && !v.cmd && v.open == 0.0) return;
  move(v, cmd);
}

void FillingProcess::step_1ms(bool coarse, bool fine, bool discharge) {
  drive(coarse_, coarse);
  drive(fine_, fine);
  drive(discharge_, discharge);
  const double leaving = (coarse_.open * coarse_.factor * cfg_.coarse_rate +
                          fine_.open * fine_.factor * cfg_.fine_rate) *
                         flow_factor_ * 0.001;
  // The ring holds what left the valves during the last fall_time: the
  // oldest entry lands now.
  const double landing = flight_[head_];
  flight_[head_] = leaving;
  if (++head_ == flight_.size()) head_ = 0;
  load_ += landing;
  landing_rate_ = landing * 1000.0;
  if (discharge_.open > 0.0)
    load_ -= std::min(load_, discharge_.open * cfg_.discharge_rate * 0.001);
}

double FillingProcess::in_flight() const {
  double s = 0.0;
  for (double x : flight_) s += x;
  return s;
}

}  // namespace plc::sim

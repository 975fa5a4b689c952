#include "pr5510/filling_process.hpp"

#include <algorithm>
#include <cmath>

namespace plc::sim {

FillingProcess::FillingProcess(const FillingConfig& c)
    : cfg_(c),
      noise_(c.seed),
      flight_(static_cast<std::size_t>(std::max(0.0, c.fall_time_s) * 1000.0 + 0.5) + 1, 0.0),
      head_(flight_.data()),
      flight_end_(flight_.data() + flight_.size()),
      load_(c.initial_load),
      valve_step_(c.valve_time_s > 0.0 ? std::min(1.0, 0.001 / c.valve_time_s) : 1.0),
      valve_instant_(c.valve_time_s <= 0.0),
      wander_(c.flow_wander * 0.0316227766) {}

double FillingProcess::in_flight() const {
  double s = 0.0;
  for (double x : flight_) s += x;
  return s;
}

}  // namespace plc::sim

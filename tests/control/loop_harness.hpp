// A control loop in virtual time for the control-block tests: a plant from
// the plant core (iec-io/sim/plant), sampled every `plant_sample`, and a
// controller called every `period`, which reads the plant's output and
// whose output holds on the plant until the next call (as a PLC output
// does between scans).
#pragma once

#include <functional>
#include <vector>

#include "plc/scan_context.hpp"
#include "plc/sim/plant/linear_plant.hpp"

namespace control_test {

using namespace std::chrono_literals;

// K / (T s + 1) with dead time L, discretised for `sample`, at rest with
// the input u0 (state K u0, dead-time buffer full of u0).
inline plc::plant::LinearPlant fopdt(double K, double T, plc::TIME L, plc::TIME sample,
                                     double u0 = 0) {
  plc::plant::DiscretiseOptions opt;
  opt.dead_time = {L};
  const double u[1] = {u0};
  plc::plant::LinearPlant p(plc::plant::discretise_zoh(plc::plant::first_order(K, T), sample, opt),
                            u);
  const double x[1] = {K * u0};
  p.set_state(x);
  return p;
}

struct Loop {
  plc::plant::LinearPlant plant;
  plc::TIME period;
  double offset = 0;  // added to the plant's output (ambient temperature)
  plc::ScanContext ctx{};
  double u = 0;                   // the controller's output as the plant sees it
  std::vector<double> t, y, out;  // one row per call

  Loop(plc::plant::LinearPlant p, plc::TIME call_period)
      : plant(std::move(p)), period(call_period) {
    ctx.period = period;
  }
  [[nodiscard]] double pv() const { return plant.outputs()[0] + offset; }

  // Calls `controller(ctx, pv)` every period for `span`; it returns the
  // output to apply. The plant then runs for one period with it.
  void run(plc::TIME span,
           const std::function<double(const plc::ScanContext&, double)>& controller) {
    const plc::TIME end = ctx.now + span;
    while (ctx.now < end) {
      u = controller(ctx, pv());
      t.push_back(std::chrono::duration<double>(ctx.now).count());
      y.push_back(pv());
      out.push_back(u);
      const double uu[1] = {u};
      for (plc::TIME s{}; s < period; s += plant.sample()) plant.step(uu);
      ctx.now += period;
      ++ctx.cycle;
    }
  }
};

// Step-response figures of y from index `from` towards `target`, starting
// at `start`: overshoot in % of the step, settling time (last time outside
// +-band % of the step) relative to t[from].
struct StepFigures {
  double overshoot_percent = 0;
  double settling_s = 0;
};

inline StepFigures step_figures(const Loop& l, std::size_t from, double start, double target,
                                double band_percent) {
  StepFigures f;
  const double step = target - start;
  double peak = 0;
  std::size_t last_out = from;
  for (std::size_t i = from; i < l.y.size(); ++i) {
    const double dev = (l.y[i] - start) / step;  // 0 .. 1 .. overshoot
    peak = std::max(peak, dev);
    if (std::fabs(l.y[i] - target) > band_percent / 100.0 * std::fabs(step)) last_out = i;
  }
  f.overshoot_percent = std::max(0.0, (peak - 1.0) * 100.0);
  f.settling_s = l.t[std::min(last_out + 1, l.t.size() - 1)] - l.t[from];
  return f;
}

}  // namespace control_test

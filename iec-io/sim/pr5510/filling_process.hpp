// The physical side of the simulated PR5510: a weigh hopper fed by a
// material stream through a coarse and a fine valve and emptied through a
// discharge valve, seen by a load cell with noise.
//
// Why the pieces exist: batching accuracy is decided by what happens after
// the PLC closes a valve (the valve's closing time and the material still
// falling, "in flight"), by flow that varies from batch to batch, and by
// measurement noise. All randomness comes from one seeded generator, so a
// run is bit-for-bit reproducible. No allocation after construction.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "plc/sim/seeded_noise.hpp"

namespace plc::sim {

struct FillingConfig {
  double coarse_rate = 5.0;      // kg/s through the coarse valve
  double fine_rate = 0.5;        // kg/s through the fine valve
  double discharge_rate = 25.0;  // kg/s out of the hopper
  double flow_variation = 0.05;  // relative: each valve opening draws rate*(1 +- this)
  double flow_wander = 0.02;     // relative random walk of the rate while open (per sqrt(s))
  double fall_time_s = 0.25;     // valve to scale: material in flight
  double valve_time_s = 0.03;    // valve opening/closing time constant
  double noise_kg = 0.002;       // load-cell noise, 1 sigma
  double impact_noise = 0.004;   // extra noise per kg/s landing (vibration)
  double initial_load = 0.0;     // kg on the scale at power-on
  std::uint64_t seed = 1;
};

class FillingProcess {
 public:
  explicit FillingProcess(const FillingConfig& c);
  // The flight ring's cursor points into its own vector.
  FillingProcess(const FillingProcess&) = delete;
  FillingProcess& operator=(const FillingProcess&) = delete;

  // Advance by exactly 1 ms with the valves as commanded. Inline (defined
  // below): the PR5510 model calls it every ms, and as a call it cost the
  // three valve flags' set-up.
  inline void step_1ms(bool coarse, bool fine, bool discharge);

  // Load on the scale (kg), without and with measurement noise.
  [[nodiscard]] double load() const { return load_; }
  // The draw first: the load and sigma() are then read from the members
  // after the noise's libm calls, not kept in registers across them (the
  // same sum and product).
  [[nodiscard]] double measured() {
    const double g = noise_.gaussian();
    return load_ + g * sigma();
  }
  // measured() in its two cases: while noise_spare() it is
  // measured_spare() (every other call), else measured_drawn() (the draw
  // of a pair, with the libm calls).
  [[nodiscard]] bool noise_spare() const { return noise_.has_spare(); }
  [[nodiscard]] double measured_spare() {
    const double g = noise_.take_spare();
    return load_ + g * sigma();
  }
  [[nodiscard]] double measured_drawn() {
    const double g = noise_.gaussian_pair();
    return load_ + g * sigma();
  }
  // Material that has left the valves but not yet landed (kg).
  [[nodiscard]] double in_flight() const;
  [[nodiscard]] double landing_rate() const { return landing_rate_; }

  // Test hooks: scale flow (e.g. a changing product), put or take material.
  void set_flow_factor(double f) { flow_factor_ = f; }
  void add_load(double kg) { load_ += kg; }

 private:
  struct Valve {
    bool cmd = false;
    double open = 0.0;    // 0..1
    double factor = 1.0;  // this opening's rate factor
    // Open and commanded open, and the last step left `open` as it was:
    // open + (1 - open) * step == open, so every later step while it stays
    // commanded open would too (the same operation on the same double).
    bool settled = false;
  };
  // step_1ms()'s parts, inline into step_1ms() (every valve, every ms): no
  // calls.
  [[gnu::always_inline]] inline void drive(Valve& v, bool cmd);
  [[gnu::always_inline]] inline void move(Valve& v, bool cmd);
  [[nodiscard]] double sigma() const { return cfg_.noise_kg + cfg_.impact_noise * landing_rate_; }

  FillingConfig cfg_;
  SeededNoise noise_;
  Valve coarse_, fine_, discharge_;
  // !discharge_.cmd && discharge_.open == 0.0, kept: only move() changes
  // either, and step_1ms() refreshes it after each move of that valve.
  bool discharge_closed_ = true;
  std::vector<double> flight_;  // kg leaving the valves per ms, ring buffer
  // The ring's next entry and its end (the vector's size is fixed at
  // construction): one load and one compare per ms, no index arithmetic.
  double* head_;
  double* flight_end_;
  double load_ = 0.0;
  double landing_rate_ = 0.0;  // kg/s
  double flow_factor_ = 1.0;
  double valve_step_;   // share of the way a valve moves in 1 ms (valve_time_s > 0)
  bool valve_instant_;  // valve_time_s <= 0.0: a valve is where it is told at once (cfg_ is fixed)
  // flow_wander * sqrt(0.001 s), the first product of move()'s wander term
  // (evaluated left to right, so the same double), once.
  double wander_;
};

inline void FillingProcess::move(Valve& v, bool cmd) {
  // The command stored only when it changes (a valve held open or closed
  // rewrote the same bool every ms); the draws in the same order.
  // (A change of the command is rare: the held command's path laid out
  // straight, not through a jump and back.)
  if (cmd != v.cmd) [[unlikely]] {
    if (cmd) v.factor = 1.0 + cfg_.flow_variation * noise_.uniform_pm1();
    v.cmd = cmd;
  }
  if (cmd) v.factor *= 1.0 + wander_ * noise_.uniform_pm1();
  // A settled valve first: settled is set only by the moving branch (never
  // with valve_instant_, which is fixed), so the instant test is left for
  // the valves that may move.
  if (cmd && v.settled) return;
  const double target = cmd ? 1.0 : 0.0;
  if (valve_instant_) {
    v.open = target;
  } else {
    const double was = v.open;
    v.open += (target - v.open) * valve_step_;
    if (!cmd && v.open < 1e-4) v.open = 0.0;
    v.settled = cmd && v.open == was;
  }
}

// A closed valve that stays closed: nothing moves (most steps, for most
// valves), and no noise is drawn.
inline void FillingProcess::drive(Valve& v, bool cmd) {
  if (!cmd && !v.cmd && v.open == 0.0) return;
  move(v, cmd);
}

inline void FillingProcess::step_1ms(bool coarse, bool fine, bool discharge) {
  drive(coarse_, coarse);
  drive(fine_, fine);
  // drive() for the discharge valve, its rest (closed: !cmd, open == 0.0)
  // kept in discharge_closed_ and its test kept for the end: a valve
  // closed and staying closed has open == 0.0, so the subtraction (open >
  // 0.0) is skipped without looking at it again.
  const bool discharge_idle = !discharge && discharge_closed_;
  if (!discharge_idle) {
    move(discharge_, discharge);
    discharge_closed_ = !discharge_.cmd && discharge_.open == 0.0;
  }
  const double leaving = (coarse_.open * coarse_.factor * cfg_.coarse_rate +
                          fine_.open * fine_.factor * cfg_.fine_rate) *
                         flow_factor_ * 0.001;
  // The ring holds what left the valves during the last fall_time: the
  // oldest entry lands now.
  const double landing = *head_;
  *head_ = leaving;
  if (++head_ == flight_end_) head_ = flight_.data();
  load_ += landing;
  landing_rate_ = landing * 1000.0;
  if (!discharge_idle && discharge_.open > 0.0)
    load_ -= std::min(load_, discharge_.open * cfg_.discharge_rate * 0.001);
}

}  // namespace plc::sim

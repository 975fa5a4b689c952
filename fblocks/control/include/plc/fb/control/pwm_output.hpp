// Time-proportioning output: a BOOL that is on for `duty` of each period, to
// drive a heater through a contactor or a solid-state relay from a
// continuous controller output (PID_Compact's Output_PWM).
//
// The duty is taken at the start of each period and holds for it (a
// contactor switches once per period, not whenever the controller output
// moves). An on time shorter than MinimumOnTime is dropped (off for the
// whole period), an off time shorter than MinimumOffTime is dropped (on for
// the whole period): a relay cannot switch for a few milliseconds. The
// resolution is the calling task's period; a period below two calls makes
// no sense and gives on/off by the duty's rounding.
#pragma once

#include <algorithm>

#include "plc/reflect.hpp"
#include "plc/types.hpp"

namespace plc::control {

struct PwmOutput {
  TIME period_start{};
  TIME on_time{};
  bool started = false;

  // duty in [0, 1] (clamped). Returns the output for `now`.
  bool step(TIME now, double duty, TIME period, TIME min_on, TIME min_off) {
    if (period <= TIME(0)) return duty >= 0.5;
    if (!started || now - period_start >= period || now < period_start) {
      // A new period; after a pause longer than a period, start afresh
      // rather than replaying the missed ones.
      if (started && now - period_start < 2 * period && now >= period_start) {
        period_start += period;
      } else {
        period_start = now;
      }
      started = true;
      duty = std::clamp(duty, 0.0, 1.0);
      on_time = TIME(static_cast<TIME::rep>(duty * static_cast<double>(period.count()) + 0.5));
      if (on_time < min_on) on_time = TIME(0);
      if (period - on_time < min_off) on_time = period;
    }
    return now - period_start < on_time;
  }
  void reset() { started = false; }

  PLC_REFLECT(period_start, on_time, started)
};

}  // namespace plc::control

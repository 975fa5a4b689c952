// The D part of a controller: Td s / (Tf s + 1) applied to a signal v, for
// a block called at uneven intervals h (the time since its last call).
//
// Discretised exactly for a signal that moves linearly between two calls
// (the best a sampled controller knows of it): over the interval dv/dt is
// the constant (v[k] - v[k-1]) / h, and the filter's ODE
// Tf dD/dt + D = Td dv/dt gives
//
//   D[k] = a D[k-1] + (1 - a) Td (v[k] - v[k-1]) / h,   a = e^(-h / Tf).
//
// Stable for every h (0 < a < 1), the same curve whoever calls it how often
// (cycle-time independence), and with Tf = 0 the plain backward difference
// Td (v[k] - v[k-1]) / h: a D part "effective for one cycle only", as the
// PID_Compact manual describes TdFiltRatio = 0.
#pragma once

#include <cmath>

#include "plc/reflect.hpp"

namespace plc::control {

struct LaggedDerivative {
  double out = 0;     // D
  double v_prev = 0;  // v at the previous call

  // h > 0 in seconds, td >= 0, tf >= 0.
  double step(double v, double h, double td, double tf) {
    const double slope = (v - v_prev) / h;
    v_prev = v;
    if (td <= 0) return out = 0;
    const double a = tf > 0 ? std::exp(-h / tf) : 0.0;
    out = a * out + (1 - a) * td * slope;
    return out;
  }
  // Bumpless start: no history, the next step sees no change.
  void reset(double v) {
    out = 0;
    v_prev = v;
  }

  PLC_REFLECT(out, v_prev)
};

}  // namespace plc::control

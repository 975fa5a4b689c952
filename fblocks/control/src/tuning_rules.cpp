#include "plc/fb/control/tuning_rules.hpp"

#include <algorithm>
#include <cmath>

namespace plc::control {

PidGains tune(TuningRule rule, const FopdtModel& m, double tau_c) {
  PidGains g;
  const double K = m.gain, T = m.time_constant, L = m.dead_time;
  if (!std::isfinite(K) || K == 0 || !(T > 0) || !(L >= 0) || !std::isfinite(T) ||
      !std::isfinite(L) || !(tau_c >= 0))
    return g;
  switch (rule) {
    case TuningRule::SIMC_PI: {
      const double tc = tau_c > 0 ? tau_c : std::max(L, T / 10);
      g.gain = T / (K * (tc + L));
      g.ti = std::min(T, 4 * (tc + L));
      g.td = 0;
      break;
    }
    case TuningRule::ZN_PI:
    case TuningRule::ZN_PID: {
      // A dead time of a millionth of T is no dead time for these rules.
      if (L <= 1e-6 * T) return g;
      const double a = K * L / T;
      if (rule == TuningRule::ZN_PI) {
        g.gain = 0.9 / a;
        g.ti = L / 0.3;
        g.td = 0;
      } else {
        g.gain = 1.2 / a;
        g.ti = 2 * L;
        g.td = 0.5 * L;
      }
      break;
    }
    default:
      return g;
  }
  g.ok = std::isfinite(g.gain) && std::isfinite(g.ti) && std::isfinite(g.td);
  return g;
}

}  // namespace plc::control

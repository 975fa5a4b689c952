// PID gains from a first-order-plus-dead-time model (K, T, L), for the ideal
// form PID_Compact uses, y = Kc (e + 1/(Ti s) e + Td s e):
//
//  SIMC_PI  Skogestad, "Simple analytic rules for model reduction and PID
//           controller tuning", J. Process Control 13 (2003), the PI rule for a
//           first-order process with delay:
//             Kc = T / (K (tau_c + L)),  Ti = min(T, 4 (tau_c + L)),  Td = 0,
//           tau_c the desired closed-loop time constant. tau_c = L is the
//           paper's "tight control" choice and our default; a model without
//           dead time would then get an infinite gain, so the default is at
//           least T / 10 [reading].
//  ZN_PI    Ziegler & Nichols, "Optimum settings for automatic controllers",
//  ZN_PID   Trans. ASME 64 (1942), the process reaction curve rules with
//           a = K L / T:  PI  Kc = 0.9 / a, Ti = 3.33 L (= L / 0.3);
//                         PID Kc = 1.2 / a, Ti = 2 L, Td = 0.5 L.
//           They need a dead time (L > 0).
//
// A negative K (a reverse-acting process) gives a negative Kc, which
// PID_Compact takes as it is (or set InvertControl and use |Kc|).
#pragma once

#include "plc/fb/control/fopdt_fit.hpp"
#include "plc/types.hpp"

namespace plc::control {

enum class TuningRule : INT { SIMC_PI = 0, ZN_PI = 1, ZN_PID = 2 };

struct PidGains {
  double gain = 0, ti = 0, td = 0;  // Kc, Ti (s), Td (s)
  bool ok = false;                  // false: the rule does not apply to the model
};

PidGains tune(TuningRule rule, const FopdtModel& m, double tau_c = 0);

}  // namespace plc::control

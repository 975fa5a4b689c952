// The PR5510 model's display rounding without the libm calls: every
// device cycle (20 ms) rounds the weight to the display step and to
// 1/100 digit, and std::round / std::llround as calls cost more than the
// rest of the rounding. The same value for every double (tests/weighing,
// PR5510Rounding): below 2^52 in magnitude the truncation to an integer
// and v - trunc(v) are exact; from 2^52 on (and NaN, the infinities) v is
// integral or out of range, and the library decides.
#pragma once

#include <cmath>
#include <cstdint>

namespace plc::sim::pr5510_rounding {

inline constexpr double kTwo52 = 4503599627370496.0;

// std::round: half away from zero, the sign of zero kept.
inline double round(double v) {
  if (!(std::fabs(v) < kTwo52)) return std::round(v);
  const double t = static_cast<double>(static_cast<std::int64_t>(v));  // toward zero
  const double f = v - t;                                              // exact
  double r = t;
  if (f >= 0.5) {
    r = t + 1.0;
  } else if (f <= -0.5) {
    r = t - 1.0;
  }
  return std::copysign(r, v);  // -0.4 and -0.0 round to -0.0
}

// std::llround.
inline long long llround(double v) {
  if (!(std::fabs(v) < kTwo52)) return std::llround(v);
  const auto t = static_cast<std::int64_t>(v);  // toward zero
  const double f = v - static_cast<double>(t);
  return t + static_cast<std::int64_t>(f >= 0.5) - static_cast<std::int64_t>(f <= -0.5);
}

}  // namespace plc::sim::pr5510_rounding

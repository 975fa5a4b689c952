// How a plant's input or output meets the process image: a linear map
// between the raw value in the image and engineering units, and the
// saturation of the physical signal.
//
//   eng = eng0 + (raw - raw0) * (eng1 - eng0) / (raw1 - raw0)
//
// The S7 analog convention (0..27648 = 0..100 %) is raw = [0, 27648],
// eng = [0, 100]. A heater cannot deliver more than 100 % or less than 0,
// a transmitter reads no more than its range: `Saturation` clamps the
// engineering value to [lo, hi] (infinite bounds: no clamp).
#pragma once

#include <algorithm>
#include <cmath>

namespace plc::plant {

struct LinearScale {
  double raw0 = 0, raw1 = 1, eng0 = 0, eng1 = 1;

  [[nodiscard]] double to_eng(double raw) const {
    return eng0 + (raw - raw0) * (eng1 - eng0) / (raw1 - raw0);
  }
  [[nodiscard]] double to_raw(double eng) const {
    return raw0 + (eng - eng0) * (raw1 - raw0) / (eng1 - eng0);
  }
};

struct Saturation {
  double lo = -INFINITY, hi = INFINITY;

  // NaN stays NaN: a caller that must not pass NaN on checks for it.
  [[nodiscard]] double apply(double v) const { return std::min(std::max(v, lo), hi); }
};

}  // namespace plc::plant

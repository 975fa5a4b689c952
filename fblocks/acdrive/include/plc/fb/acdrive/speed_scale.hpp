// Speed scaling of the AC/DC Drive object (toyo-vf66-devicenet.md §6.1,
// 0x2A attrs 7/8/22): bus value = r/min x 2^SpeedScale, r/min = bus value /
// 2^SpeedScale (the manual's worked examples: 4567 at scale 3 = 570.875
// r/min; 789.5 r/min at scale 3 = 6316). §13.4 item 15: the attr-22 formula
// read literally could have the opposite sign; the examples decide.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>

namespace plc::acdrive {

inline double bus_to_rpm(std::int16_t bus, int speed_scale) {
  return std::ldexp(static_cast<double>(bus), -speed_scale);
}

// The INT for `rpm` (rounded to the nearest LSB); nullopt when it does not
// fit an INT at this scale (±4095.875 r/min at scale 3, §13.3) or is not
// finite: the caller refuses it rather than wrap it.
inline std::optional<std::int16_t> rpm_to_bus(double rpm, int speed_scale) {
  if (!std::isfinite(rpm)) return std::nullopt;
  const double v = std::nearbyint(std::ldexp(rpm, speed_scale));
  if (v < -32768.0 || v > 32767.0) return std::nullopt;
  return static_cast<std::int16_t>(v);
}

// V/f mode (§6.2, with the "x 6" misprint read as x 60, §13.4 item 3):
// the bus value is the synchronous speed f x 60 / (poles / 2).
inline double hz_to_rpm(double hz, unsigned poles) { return hz * 120.0 / poles; }
inline double rpm_to_hz(double rpm, unsigned poles) { return rpm * poles / 120.0; }

}  // namespace plc::acdrive

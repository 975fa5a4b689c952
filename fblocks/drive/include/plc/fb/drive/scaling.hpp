// Normalisations of the E1 process data (spec §2 Table 3.1.1, §7.1, §7.6).
//
//   NSOLL_B / NIST_B   0x40000000 = 100 % of the speed reference (Pt317 rpm
//                      rotary, Pt386 x 100 mm/s linear); ~ +/-200 % range
//   MDI_VELOCITY       1 = 1000 CU/min, 0 .. 2^31-1
//   MDI_ACC / MDI_DEC  0x4000 = 100 % of the Pt534 / Pt537 reference, 0..16384
//   OVERRIDE           0x4000 = 100 % of the MDI velocity, 0..32767 (~200 %)
//
// Setpoints (PLC -> drive) go through the checked to_* conversions below:
// a value that is not finite or whose wire value falls outside the field's
// range of Table 3.1.1 gives std::nullopt, and the blocks refuse it with an
// ErrorID (diag_codes.hpp). A setpoint is never wrapped (3e9 CU would go out
// as -1294967296 and move the axis the wrong way) nor clamped silently.
// Actual values (drive -> PLC, and the simulated drive's own NIST_B) use the
// saturating conversions: a reading is shown as near as the field allows.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>

namespace plc::drive {

inline constexpr double kNsollB100 = 1073741824.0;  // 0x40000000
inline constexpr double kPercent14 = 16384.0;       // 0x4000 (MDI_ACC/DEC, OVERRIDE)

namespace detail {
inline constexpr double kInt32Min = -2147483648.0;
inline constexpr double kInt32Max = 2147483647.0;
// std::llround (half away from zero) without the libm call: the simulated
// drive rounds its position and speed every step, and the call costs more
// than the rest of the rounding. The same value for every double: below
// 2^52 in magnitude v - trunc(v) is exact; from 2^52 on (and NaN, the
// infinities) v is integral or out of range, and std::llround decides.
inline std::int64_t llround_inline(double v) {
  if (!(std::fabs(v) < 4503599627370496.0)) return std::llround(v);
  const auto t = static_cast<std::int64_t>(v);  // toward zero
  const double f = v - static_cast<double>(t);
  return t + static_cast<std::int64_t>(f >= 0.5) - static_cast<std::int64_t>(f <= -0.5);
}
inline std::int64_t round_sat(double v, double lo, double hi) {
  if (std::isnan(v)) return 0;
  if (v < lo) v = lo;
  if (v > hi) v = hi;
  return llround_inline(v);
}
// Rounds to the nearest wire value of type T; std::nullopt if `v` is not
// finite or the rounded value is outside [lo, hi].
template <class T>
std::optional<T> round_in(double v, double lo, double hi) {
  if (!std::isfinite(v)) return std::nullopt;
  const double r = std::round(v);
  if (r < lo || r > hi) return std::nullopt;
  return static_cast<T>(r);
}
}  // namespace detail

// ---- setpoints: checked (Table 3.1.1 ranges) ----

// Position or distance in CU -> MDI_TARPOS (Int32, 1 = 1 CU).
inline std::optional<std::int32_t> to_mdi_tarpos(double cu) {
  return detail::round_in<std::int32_t>(cu, detail::kInt32Min, detail::kInt32Max);
}
// CU/s -> MDI_VELOCITY (0 .. 2^31-1, 1 = 1000 CU/min; negative is out of range).
inline std::optional<std::int32_t> to_mdi_velocity(double cu_per_s) {
  return detail::round_in<std::int32_t>(cu_per_s * 60.0 / 1000.0, 0, detail::kInt32Max);
}
// Percent -> MDI_ACC / MDI_DEC (0 .. 16384, 0x4000 = 100 %).
inline std::optional<std::int16_t> to_mdi_acc(double percent) {
  return detail::round_in<std::int16_t>(percent / 100.0 * kPercent14, 0, 16384);
}
// Percent -> OVERRIDE (0 .. 32767, 0x4000 = 100 %, so at most ~199.99 %).
inline std::optional<std::uint16_t> to_override(double percent) {
  return detail::round_in<std::uint16_t>(percent / 100.0 * kPercent14, 0, 32767);
}
// Speed (unit of `reference`, e.g. rpm) -> NSOLL_B (Int32, 0x40000000 =
// 100 %, so |speed| < 200 % of the reference); the reference must be > 0.
inline std::optional<std::int32_t> to_nsoll_b(double speed, double reference) {
  if (!(reference > 0) || !std::isfinite(reference)) return std::nullopt;
  return detail::round_in<std::int32_t>(speed / reference * kNsollB100, detail::kInt32Min,
                                        detail::kInt32Max);
}

// ---- actual values: saturating ----

// speed (same unit as `reference`, e.g. rpm) -> NIST_B (the simulated drive's
// actual speed), saturated at the Int32 range.
inline std::int32_t speed_to_nsoll_b(double speed, double reference) {
  if (reference <= 0) return 0;
  return static_cast<std::int32_t>(
      detail::round_sat(speed / reference * kNsollB100, detail::kInt32Min, detail::kInt32Max));
}
// NIST_B (or NSOLL_B) -> speed in the unit of `reference`.
inline double nist_b_to_speed(std::int32_t nist_b, double reference) {
  return static_cast<double>(nist_b) / kNsollB100 * reference;
}

// Actual CU/s -> 1000 CU/min units (SinaPos ActVelocity); negative becomes 0.
inline std::int32_t cu_per_s_to_mdi_velocity(double cu_per_s) {
  return static_cast<std::int32_t>(
      detail::round_sat(cu_per_s * 60.0 / 1000.0, 0, detail::kInt32Max));
}
inline double mdi_velocity_to_cu_per_s(std::int32_t mdi_velocity) {
  return static_cast<double>(mdi_velocity) * 1000.0 / 60.0;
}

inline double mdi_acc_to_percent(std::int16_t v) { return v / kPercent14 * 100.0; }

inline double override_to_percent(std::uint16_t v) { return v / kPercent14 * 100.0; }

// rpm <-> CU/s for a rotary axis with `cu_per_rev` control units per motor
// revolution (the electronic gear, E1 user manual §6.11).
inline double rpm_to_cu_per_s(double rpm, double cu_per_rev) { return rpm / 60.0 * cu_per_rev; }
inline double cu_per_s_to_rpm(double v, double cu_per_rev) { return v * 60.0 / cu_per_rev; }

// [INF] spec §10.3.6: the acceleration reference Pt534 (and Pt537, Pt538,
// Pt30A) is a ramp *time*; we read it as the time from 0 to the reference
// speed Pt317. So the 100 % acceleration in CU/s^2 is:
inline double ramp_time_to_accel(double ref_speed_cu_per_s, double ramp_ms) {
  return ramp_ms > 0 ? ref_speed_cu_per_s / (ramp_ms / 1000.0) : 0.0;
}

}  // namespace plc::drive

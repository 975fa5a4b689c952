#include "plc/fb/control/pid_compact.hpp"

#include <algorithm>
#include <cmath>

#include "plc/fb/control/error_bits.hpp"

namespace plc::control {
namespace {

double seconds(TIME t) { return std::chrono::duration<double>(t).count(); }
bool finite(double v) { return std::isfinite(v); }

constexpr std::uint32_t kStopsAutomatic =
    error_bits::kInputPerInvalid | error_bits::kInputInvalid | error_bits::kSetpointInvalid |
    error_bits::kInvalidParameters | error_bits::kSamplingTime;

}  // namespace

DWORD PID_Compact::check_inputs(double h) {
  std::uint32_t e = 0;
  const bool params_ok =
      finite(Gain) && finite(Ti) && Ti >= 0 && finite(Td) && Td >= 0 && finite(TdFiltRatio) &&
      TdFiltRatio >= 0 && finite(PWeighting) && PWeighting >= 0 && PWeighting <= 1 &&
      finite(DWeighting) && DWeighting >= 0 && DWeighting <= 1 && finite(OutputUpperLimit) &&
      finite(OutputLowerLimit) && OutputLowerLimit < OutputUpperLimit &&
      InputLowerLimit < InputUpperLimit && SetpointLowerLimit <= SetpointUpperLimit &&
      finite(SetpointRamp) && SetpointRamp >= 0 && InputScalingUpperIn != InputScalingLowerIn;
  if (!params_ok) e |= error_bits::kInvalidParameters;
  if (h <= 0) e |= error_bits::kSamplingTime;
  if (!finite(Setpoint)) e |= error_bits::kSetpointInvalid;
  if (!finite(Disturbance)) e |= error_bits::kDisturbanceInvalid;
  return e;
}

void PID_Compact::operator()(const ScanContext& ctx) {
  // h: the time since the previous call; the first call takes the task's
  // period (there is no previous call to measure from).
  const double h = called_ ? seconds(ctx.now - last_call_) : seconds(ctx.period);
  last_call_ = ctx.now;
  called_ = true;

  const bool ack_edge = ErrorAck && !ack_prev_;
  const bool reset_edge = Reset && !reset_prev_;
  ack_prev_ = ErrorAck;
  reset_prev_ = Reset;
  if (ack_edge || reset_edge) ErrorBits = 0;

  std::uint32_t pending = check_inputs(h);

  // Process value.
  double x = Input;
  if (InputPerOn) {
    if (Input_PER > 32511 || Input_PER < -32512) pending |= error_bits::kInputPerInvalid;
    x = InputScalingLowerOut + (double(Input_PER) - InputScalingLowerIn) *
                                   (double(InputScalingUpperOut) - InputScalingLowerOut) /
                                   (double(InputScalingUpperIn) - InputScalingLowerIn);
  } else if (!finite(x)) {
    pending |= error_bits::kInputInvalid;
  }
  if (finite(x)) ScaledInput = static_cast<REAL>(x);
  // An invalid analog word (overflow or underflow) is a broken signal, not a
  // process value out of its limits: 16#0002 alone, as the manual lists it.
  if (finite(x) && !(pending & error_bits::kInputPerInvalid)) {
    if (x > InputUpperLimit || x < InputLowerLimit) pending |= error_bits::kInputOutOfLimits;
    InputWarning_H = x >= InputUpperWarning;
    InputWarning_L = x <= InputLowerWarning;
  }

  // Setpoint within its limits.
  double w = Setpoint;
  SetpointLimit_H = finite(w) && w >= SetpointUpperLimit;
  SetpointLimit_L = finite(w) && w <= SetpointLowerLimit;
  if (finite(w)) w = std::clamp(w, double(SetpointLowerLimit), double(SetpointUpperLimit));

  const double lo = OutputLowerLimit, hi = OutputUpperLimit;
  auto substitute = [&]() -> double {
    if (!SetSubstituteOutput) return last_output_;
    if (!finite(SubstituteOutput)) {
      pending |= error_bits::kSubstituteOutputInvalid;
      return lo;
    }
    return std::clamp(double(SubstituteOutput), std::min(lo, hi), std::max(lo, hi));
  };

  double out = 0;
  if (Reset) {
    // Inactive while Reset is TRUE: output 0, integral action cleared.
    State = INT(Mode::Inactive);
    integral_ = 0;
    last_output_ = 0;
    was_automatic_ = false;
  } else if (ManualEnable) {
    State = INT(Mode::Manual);
    if (finite(ManualValue)) {
      out = std::clamp(double(ManualValue), std::min(lo, hi), std::max(lo, hi));
    } else {
      pending |= error_bits::kManualValueInvalid;
      out = substitute();
    }
    was_automatic_ = false;
  } else if ((pending & kStopsAutomatic) ||
             ((pending & error_bits::kInputOutOfLimits) && !ActivateRecoverMode)) {
    was_automatic_ = false;
    if (ActivateRecoverMode) {
      State = INT(Mode::Substitute);
      out = substitute();
    } else {
      State = INT(Mode::Inactive);
      out = 0;
    }
  } else {
    State = INT(Mode::Automatic);
    automatic(h, x, w);
    out = double(PAction) + integral_ + double(DAction) +
          (finite(Disturbance) ? double(Disturbance) : 0.0);
    if (!finite(out)) {
      pending |= error_bits::kOutputFailed;
      was_automatic_ = false;
      State = INT(ActivateRecoverMode ? Mode::Substitute : Mode::Inactive);
      out = ActivateRecoverMode ? substitute() : 0.0;
    } else {
      out = std::clamp(out, lo, hi);
    }
  }
  ErrorBits = ErrorBits | pending;
  Error = pending != 0;
  finish(ctx, out);
}

void PID_Compact::automatic(double h, double x, double w) {
  const double kp = InvertControl ? -double(Gain) : double(Gain);
  const double lo = OutputLowerLimit, hi = OutputUpperLimit;
  const double dist = finite(Disturbance) ? double(Disturbance) : 0.0;
  const bool start = !was_automatic_;
  // Setpoint ramp: from the process value when automatic mode begins.
  if (SetpointRamp > 0) {
    if (start) ramp_sp_ = x;
    const double step = double(SetpointRamp) * h;
    ramp_sp_ += std::clamp(w - ramp_sp_, -step, step);
    w = ramp_sp_;
  } else {
    ramp_sp_ = w;
  }
  EffectiveSetpoint = static_cast<REAL>(w);
  const double p = kp * (double(PWeighting) * w - x);
  const double v = kp * (double(DWeighting) * w - x);
  double d = 0;
  if (start) {
    derivative_.reset(v);
    // Bumpless: the integral action takes up the difference, so the first
    // automatic output is the last one.
    integral_ = last_output_ - p - dist;
    was_automatic_ = true;
  } else {
    d = derivative_.step(v, h, Td, double(TdFiltRatio) * Td);
    if (Ti > 0) {
      const double di = kp * h / double(Ti) * (w - x);
      // Anti-windup: I moves towards a limit only as far as the output
      // reaches it. Skipping a whole increment instead would leave the
      // output up to one increment short of a limit it should sit at.
      const double rest = p + d + dist;
      if (di > 0) {
        integral_ = std::max(integral_, std::min(integral_ + di, hi - rest));
      } else if (di < 0) {
        integral_ = std::min(integral_, std::max(integral_ + di, lo - rest));
      }
    }
  }
  PAction = static_cast<REAL>(p);
  IAction = static_cast<REAL>(integral_);
  DAction = static_cast<REAL>(d);
}

void PID_Compact::finish(const ScanContext& ctx, double out) {
  if (finite(out)) last_output_ = out;
  Output = static_cast<REAL>(out);
  const double per = std::round(out * 27648.0 / 100.0);
  Output_PER = static_cast<INT>(std::clamp(per, -32768.0, 32767.0));
  if (State == INT(Mode::Inactive)) {
    pwm_.reset();
    Output_PWM = false;
  } else {
    Output_PWM = pwm_.step(ctx.now, out / 100.0, PwmPeriod, MinimumOnTime, MinimumOffTime);
  }
}

}  // namespace plc::control

// PID_Compact: a continuous PID controller in the style of TIA Portal's
// PID_Compact (V2; Siemens function manual "PID control", A5E35300227,
// section 9.1), for a process value in engineering units and an output in
// percent. Not a clone: no pretuning or fine tuning inside the block (the
// tuning aid is PID_StepTune, pid_step_tune.hpp), no Mode/ModeActivate
// (ManualEnable and Reset choose the mode), and a setpoint ramp it does not
// have. Every reading is listed in fblocks/control/README.md.
//
// The algorithm (the manual's PIDT1 with weighting of the P and D actions):
//
//   y = Kp [ (b w - x) + 1/(Ti s) (w - x) + Td s / (a Td s + 1) (c w - x) ] + Disturbance
//
// Kp = Gain, Ti, Td in seconds, a = TdFiltRatio, b = PWeighting,
// c = DWeighting (default 0: the derivative acts on the measurement only,
// so a setpoint step does not kick the output; the manual's PID_Temp table
// gives 1.0 [reading]), w = the setpoint after its limits and ramp,
// x = ScaledInput. InvertControl negates Kp (a cooling loop).
//
// Discrete, per call, with h = the time since the previous call (ctx.now;
// cycle-time independence: the block may run in any task, the gains are in
// seconds, not in calls):
//   P = Kp (b w - x)
//   D = lagged_derivative(Kp (c w - x), h, Td, a Td)         (exact, see there)
//   dI = Kp h / Ti (w - x);   I += dI, but towards a limit only as far as
//                             P + I + D + Disturbance reaches it (clamped
//                             conditional integration: I never grows while
//                             the output it would move is at a limit, so it
//                             cannot wind up, and the output does reach
//                             the limit)
//   Output = clamp(P + I + D + Disturbance, OutputLowerLimit, OutputUpperLimit)
// Ti = 0 switches the integral action off, Td = 0 the derivative action.
//
// Modes (State, as the manual numbers them): 0 inactive (Reset, or an error
// without ActivateRecoverMode: Output 0), 3 automatic, 4 manual (Output =
// ManualValue within the output limits), 5 substitute output with error
// monitoring (SubstituteOutput if SetSubstituteOutput, else the last valid
// output). Manual -> automatic and inactive -> automatic are bumpless: I is
// set so that the first automatic output equals the last output, the D
// history starts afresh, and with a SetpointRamp the ramp starts at the
// process value. Automatic -> manual takes ManualValue (bumpless when the
// program tracks ManualValue := Output in automatic, as the TIA
// commissioning panel does).
//
// Errors: ErrorBits (error_bits.hpp) latch until a rising edge of ErrorAck
// or Reset; Error is TRUE while an error is pending in this call.
//
// Outputs: Output (REAL, %), Output_PER (INT, Output x 27648 / 100) and
// Output_PWM (BOOL, pwm_output.hpp: duty = Output / 100 over PwmPeriod),
// all three at once.
//
// Layout: one call is a few dozen flops and one exp() (the D filter, only
// with Td > 0); tests/bench measures it.
#pragma once

#include "plc/fb/control/lagged_derivative.hpp"
#include "plc/fb/control/pwm_output.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::control {

struct PID_Compact {
  enum class Mode : INT { Inactive = 0, Automatic = 3, Manual = 4, Substitute = 5 };

  // ---------------- inputs ----------------
  REAL Setpoint{};
  REAL Input{};     // process value, engineering units (InputPerOn = FALSE)
  INT Input_PER{};  // analog word (InputPerOn = TRUE), scaled by InputScaling
  REAL Disturbance{};
  BOOL ManualEnable{};
  REAL ManualValue{};
  BOOL ErrorAck{};
  BOOL Reset{};

  // ---------------- configuration (TIA: Config.*) ----------------
  BOOL InputPerOn{};
  BOOL InvertControl{};
  REAL InputUpperLimit = 120.0f;
  REAL InputLowerLimit = 0.0f;
  REAL InputUpperWarning = 3.402823e+38f;
  REAL InputLowerWarning = -3.402823e+38f;
  REAL OutputUpperLimit = 100.0f;
  REAL OutputLowerLimit = 0.0f;
  REAL SetpointUpperLimit = 3.402823e+38f;
  REAL SetpointLowerLimit = -3.402823e+38f;
  REAL InputScalingUpperIn = 27648.0f;  // Config.InputScaling.UpperPointIn
  REAL InputScalingUpperOut = 100.0f;
  REAL InputScalingLowerIn = 0.0f;
  REAL InputScalingLowerOut = 0.0f;
  REAL SetpointRamp{};  // units per second, 0 = the setpoint acts at once
  BOOL ActivateRecoverMode = true;
  BOOL SetSubstituteOutput = true;
  REAL SubstituteOutput{};
  TIME PwmPeriod = std::chrono::seconds(1);
  TIME MinimumOnTime{};
  TIME MinimumOffTime{};

  // ---------------- controller parameters (TIA: Retain.CtrlParams.*) ----------------
  REAL Gain = 1.0f;
  REAL Ti = 20.0f;  // s, 0 = no integral action
  REAL Td = 0.0f;   // s, 0 = no derivative action
  REAL TdFiltRatio = 0.2f;
  REAL PWeighting = 1.0f;
  REAL DWeighting = 0.0f;

  // ---------------- outputs ----------------
  REAL ScaledInput{};
  REAL Output{};
  INT Output_PER{};
  BOOL Output_PWM{};
  BOOL SetpointLimit_H{};
  BOOL SetpointLimit_L{};
  BOOL InputWarning_H{};
  BOOL InputWarning_L{};
  INT State{};
  BOOL Error{};
  DWORD ErrorBits{};
  // Diagnostics (not in TIA): the setpoint the algorithm used (after limits
  // and ramp) and the three actions of the last automatic call.
  REAL EffectiveSetpoint{};
  REAL PAction{};
  REAL IAction{};
  REAL DAction{};

  void operator()(const ScanContext& ctx);

  // ---------------- internal ----------------
  LREAL integral_{};
  LREAL last_output_{};  // last valid output (substitute value, bumpless start)
  LREAL ramp_sp_{};
  LaggedDerivative derivative_;
  PwmOutput pwm_;
  TIME last_call_{};
  BOOL called_{};
  BOOL was_automatic_{};
  BOOL ack_prev_{};
  BOOL reset_prev_{};

  PLC_REFLECT(Setpoint, Input, Input_PER, Disturbance, ManualEnable, ManualValue, ErrorAck, Reset,
              InputPerOn, InvertControl, InputUpperLimit, InputLowerLimit, InputUpperWarning,
              InputLowerWarning, OutputUpperLimit, OutputLowerLimit, SetpointUpperLimit,
              SetpointLowerLimit, InputScalingUpperIn, InputScalingUpperOut, InputScalingLowerIn,
              InputScalingLowerOut, SetpointRamp, ActivateRecoverMode, SetSubstituteOutput,
              SubstituteOutput, PwmPeriod, MinimumOnTime, MinimumOffTime, Gain, Ti, Td, TdFiltRatio,
              PWeighting, DWeighting, ScaledInput, Output, Output_PER, Output_PWM, SetpointLimit_H,
              SetpointLimit_L, InputWarning_H, InputWarning_L, State, Error, ErrorBits,
              EffectiveSetpoint, PAction, IAction, DAction, integral_, last_output_, ramp_sp_,
              derivative_, pwm_, last_call_, called_, was_automatic_, ack_prev_, reset_prev_)
  PLC_INTERNAL(State, ErrorBits, integral_, last_output_, ramp_sp_, derivative_, pwm_, last_call_,
               called_, was_automatic_, ack_prev_, reset_prev_)

 private:
  [[nodiscard]] DWORD check_inputs(double h);
  void automatic(double h, double x, double w);
  void finish(const ScanContext& ctx, double out);
};

}  // namespace plc::control

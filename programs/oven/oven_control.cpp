#include "oven_control.hpp"

namespace oven {

OvenControl::OvenControl() {
  tune.BaseOutput = 0.0f;
  tune.StepSize = 30.0f;
  tune.SettleTime = 60s;
  tune.TestTime = 25min;  // dead time + 5 x the dominant lag
  tune.Rule = INT(control::TuningRule::SIMC_PI);
  pid.InputPerOn = true;
  pid.InputScalingUpperOut = 300.0f;  // 27648 = 300 degC
  pid.InputUpperLimit = 300.0f;
  pid.InputLowerLimit = -10.0f;
}

void OvenControl::cycle(const ScanContext& ctx) {
  temperature = static_cast<REAL>(INT(temperature_raw) * (300.0 / 27648.0));
  switch (step) {
    case Step::Tune:
      tune.Execute = true;
      tune.Input = temperature;
      tune(ctx);
      pid.ManualEnable = true;
      pid.ManualValue = tune.Output;
      if (tune.Done) {
        pid.Gain = tune.Gain;
        pid.Ti = tune.Ti;
        pid.Td = tune.Td;
        pid.ManualEnable = false;
        control_since = ctx.now;
        step = Step::Control;
      } else if (tune.Error) {
        step = Step::Failed;
      }
      break;
    case Step::Control:
      tune.Execute = false;
      break;
    case Step::Failed:
      pid.ManualEnable = true;
      pid.ManualValue = 0.0f;
      break;
  }
  // The scan that hands over to automatic uses the measured temperature as
  // setpoint, the next ones `setpoint`: a bumpless transfer straight to a
  // distant setpoint would put the whole error into the integral action
  // (the first output equals the last), and only the integral would close
  // the gap, over many minutes. So the loop takes over at zero error and
  // then answers a setpoint step as tuned.
  if (step == Step::Control && ctx.now == control_since) {
    pid.Setpoint = temperature;
  } else {
    pid.Setpoint = step == Step::Control && ctx.now - control_since >= second_setpoint_after
                       ? second_setpoint
                       : setpoint;
  }
  pid.Input_PER = temperature_raw;
  pid(ctx);
  heater = pid.Output_PER;
}

PLC_REGISTER_PROGRAM(OvenControl)

}  // namespace oven

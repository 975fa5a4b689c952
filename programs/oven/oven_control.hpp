// The oven cell's program: a heated oven (the sim plugin's `plant` model,
// cell.yaml) tuned by a step test and then held at its setpoint.
//
//   Tune     PID_Compact in manual; PID_StepTune drives its ManualValue:
//            a baseline at 0 % heater, then a 30 % step, a FOPDT model
//            fitted to the response, SIMC gains proposed.
//   Control  the proposed Gain/Ti/Td copied into PID_Compact, which goes
//            to automatic (bumpless from the step test's 30 %, for one scan
//            at the measured temperature as setpoint), then steps to
//            `setpoint`, and to `second_setpoint` after
//            `second_setpoint_after`.
//   Failed   the step test ended in an error: heater off, ErrorID kept in
//            tune.ErrorID.
//
// The temperature comes as an S7 analog word (0..27648 = 0..300 degC), the
// heater goes out as one (0..27648 = 0..100 %).
#pragma once

#include "plc/fb/control/pid_compact.hpp"
#include "plc/fb/control/pid_step_tune.hpp"
#include "plc/io/located.hpp"
#include "plc/program.hpp"

namespace oven {

using namespace plc;
using namespace std::chrono_literals;

class OvenControl : public ProgramBase<OvenControl> {
 public:
  enum class Step : INT { Tune = 1, Control = 2, Failed = 3 };

  io::Located<INT> temperature_raw{"%IW0"};
  io::Located<INT> heater{"%QW0"};

  REAL temperature{};  // degC, for traces and the HMI
  REAL setpoint = 150.0f;
  REAL second_setpoint = 200.0f;
  TIME second_setpoint_after = 20min;

  Step step = Step::Tune;
  TIME control_since{};
  control::PID_StepTune tune;
  control::PID_Compact pid;

  OvenControl();
  void cycle(const ScanContext& ctx) override;

  PLC_REFLECT(temperature_raw, heater, temperature, setpoint, second_setpoint,
              second_setpoint_after, step, control_since, tune, pid)
  PLC_INTERNAL(step, control_since)
};

}  // namespace oven

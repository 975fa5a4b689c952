// PID_StepTune: the tuning aid. It runs an open-loop step test on the
// plant, identifies a first-order-plus-dead-time model by least squares
// (fopdt_fit.hpp) and proposes PID gains by a named rule (tuning_rules.hpp),
// with the fit's quality. Execute-style (PLCopen).
//
// The program routes the block's Output to the plant while the test runs,
// typically as PID_Compact's ManualValue with ManualEnable (so the PID takes
// over bumplessly afterwards):
//
//   Baseline  (Phase 1) Output = BaseOutput for SettleTime: the process
//             value's mean and noise there are the steady state y0.
//   Step      (Phase 2) Output = BaseOutput + StepSize for TestTime; the
//             deviation Input - y0 is recorded (kMaxSamples samples at most,
//             at a whole multiple of the task period).
//   Identify  (Phase 3) one least-squares iteration per call (each scan
//             stays short), Output held at BaseOutput + StepSize.
//   Done      (Phase 4) ProcessGain, TimeConstant, DeadTime, FitPercent,
//             RSquared, NoiseSigma and the proposal Gain/Ti/Td; Output still
//             BaseOutput + StepSize (the program decides what comes next).
//   Error (5) / Aborted (6): Output = BaseOutput.
//
// TestTime should cover the dead time plus 3 to 5 time constants: the fit
// needs the response to level off. ErrorID:
//   16#8001 invalid inputs (StepSize 0 or not finite, TestTime <= 0,
//           SettleTime < 0, an unknown Rule, TauC < 0)
//   16#8002 Input is not a number
//   16#8003 no response: the final deviation is below 5 sigma of the
//           baseline noise (a step too small, the wrong output, a plant off)
//   16#8004 the identification found no model (T <= 0, K not finite)
//   16#8005 the rule does not apply to the model (ZN without dead time)
// Done, Error and CommandAborted hold while Execute stays TRUE (at least
// one call). Abort (level) stops a running test.
#pragma once

#include <array>

#include "plc/fb/control/fopdt_fit.hpp"
#include "plc/fb/control/tuning_rules.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::control {

struct PID_StepTune {
  static constexpr std::size_t kMaxSamples = 2000;
  enum class TunePhase : INT {
    Idle = 0,
    Baseline = 1,
    Step = 2,
    Identify = 3,
    Done = 4,
    Error = 5,
    Aborted = 6
  };

  // ---------------- inputs ----------------
  BOOL Execute{};
  BOOL Abort{};
  REAL Input{};
  REAL BaseOutput{};
  REAL StepSize = 10.0f;
  TIME SettleTime = std::chrono::seconds(10);
  TIME TestTime = std::chrono::seconds(60);
  INT Rule = INT(TuningRule::SIMC_PI);
  REAL TauC{};  // s; 0: the rule's default

  // ---------------- outputs ----------------
  BOOL Busy{};
  BOOL Done{};
  BOOL Error{};
  WORD ErrorID{};
  BOOL CommandAborted{};
  REAL Output{};
  INT Phase{};
  REAL ProcessGain{};
  REAL TimeConstant{};
  REAL DeadTime{};
  REAL FitPercent{};
  REAL RSquared{};
  REAL NoiseSigma{};
  REAL Gain{};
  REAL Ti{};
  REAL Td{};
  INT Iterations{};
  INT Samples{};

  void operator()(const ScanContext& ctx);

  // The recorded deviations (Samples of them) and their sample time, for a
  // program or test that wants to plot or check them.
  [[nodiscard]] std::span<const double> recorded() const { return {y_.data(), n_}; }
  [[nodiscard]] double sample_time() const { return ts_; }

  // ---------------- internal ----------------
  std::array<double, kMaxSamples> y_{};
  std::size_t n_ = 0;
  double ts_ = 0;
  LREAL base_sum_{}, base_sq_{};
  LREAL y0_{}, base_sigma_{};
  DINT base_count_{};
  TIME phase_start_{};
  BOOL exec_prev_{};
  FopdtFitter fitter_;

  PLC_REFLECT(Execute, Abort, Input, BaseOutput, StepSize, SettleTime, TestTime, Rule, TauC, Busy,
              Done, Error, ErrorID, CommandAborted, Output, Phase, ProcessGain, TimeConstant,
              DeadTime, FitPercent, RSquared, NoiseSigma, Gain, Ti, Td, Iterations, Samples,
              base_sum_, base_sq_, y0_, base_sigma_, base_count_, phase_start_, exec_prev_)
  PLC_INTERNAL(Phase, base_sum_, base_sq_, y0_, base_sigma_, base_count_, phase_start_, exec_prev_)

 private:
  void fail(WORD id);
  void finish_identification();
};

}  // namespace plc::control

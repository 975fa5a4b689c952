#include "plc/fb/control/pid_step_tune.hpp"

#include <cmath>

namespace plc::control {
namespace {

double seconds(TIME t) { return std::chrono::duration<double>(t).count(); }

}  // namespace

void PID_StepTune::fail(WORD id) {
  Phase = INT(TunePhase::Error);
  Busy = false;
  Error = true;
  ErrorID = id;
  Output = BaseOutput;
}

void PID_StepTune::operator()(const ScanContext& ctx) {
  const bool start = Execute && !exec_prev_;
  exec_prev_ = Execute;
  auto phase = static_cast<TunePhase>(Phase);

  // Finished states hold while Execute stays TRUE, then go idle.
  if ((phase == TunePhase::Done || phase == TunePhase::Error || phase == TunePhase::Aborted) &&
      !Execute && !start) {
    Phase = INT(TunePhase::Idle);
    Done = Error = CommandAborted = false;
    ErrorID = 0;
    return;
  }
  if (start && !Busy) {
    Done = Error = CommandAborted = false;
    ErrorID = 0;
    Iterations = Samples = 0;
    const bool ok = std::isfinite(StepSize) && StepSize != 0 && TestTime > TIME(0) &&
                    SettleTime >= TIME(0) && Rule >= 0 && Rule <= 2 && std::isfinite(TauC) &&
                    TauC >= 0 && std::isfinite(BaseOutput);
    if (!ok) return fail(0x8001);
    Busy = true;
    Phase = INT(TunePhase::Baseline);
    phase_start_ = ctx.now;
    base_sum_ = base_sq_ = 0;
    base_count_ = 0;
    n_ = 0;
    phase = TunePhase::Baseline;
  }
  if (!Busy) return;
  if (Abort) {
    Phase = INT(TunePhase::Aborted);
    Busy = false;
    CommandAborted = true;
    Output = BaseOutput;
    return;
  }
  if ((phase == TunePhase::Baseline || phase == TunePhase::Step) && !std::isfinite(Input))
    return fail(0x8002);

  switch (phase) {
    case TunePhase::Baseline: {
      Output = BaseOutput;
      base_sum_ += Input;
      base_sq_ += double(Input) * Input;
      ++base_count_;
      if (ctx.now - phase_start_ >= SettleTime) {
        y0_ = base_sum_ / base_count_;
        base_sigma_ = std::sqrt(std::max(0.0, base_sq_ / base_count_ - y0_ * y0_));
        // Sample time: the record spread over at most kMaxSamples, at a
        // whole multiple of the task period.
        const double period = ctx.period > TIME(0) ? seconds(ctx.period) : 1e-3;
        const double want = seconds(TestTime) / double(kMaxSamples - 1);
        ts_ = std::ceil(want / period - 1e-9) * period;
        if (ts_ < period) ts_ = period;
        Phase = INT(TunePhase::Step);
        phase_start_ = ctx.now;
        n_ = 0;
        Output = BaseOutput + StepSize;
        // The sample at t = 0 is this call's value: the step takes effect
        // from the next device exchange on.
        y_[n_++] = Input - y0_;
      }
      break;
    }
    case TunePhase::Step: {
      Output = BaseOutput + StepSize;
      const double t = seconds(ctx.now - phase_start_);
      const auto due = static_cast<std::size_t>(std::floor(t / ts_ + 1e-9));
      while (n_ <= due && n_ < kMaxSamples) y_[n_++] = Input - y0_;
      Samples = static_cast<INT>(n_);
      if (ctx.now - phase_start_ >= TestTime || n_ >= kMaxSamples) {
        const double final_dev = [&] {
          const std::size_t tail = std::max<std::size_t>(1, n_ / 10);
          double s = 0;
          for (std::size_t j = n_ - tail; j < n_; ++j) s += y_[j];
          return s / double(tail);
        }();
        if (std::fabs(final_dev) <= 5 * base_sigma_ || final_dev == 0) return fail(0x8003);
        if (!fitter_.start({y_.data(), n_}, ts_, StepSize)) return fail(0x8004);
        Phase = INT(TunePhase::Identify);
      }
      break;
    }
    case TunePhase::Identify: {
      Output = BaseOutput + StepSize;
      if (fitter_.iterate()) finish_identification();
      Iterations = static_cast<INT>(fitter_.result().iterations);
      break;
    }
    default:
      break;
  }
}

void PID_StepTune::finish_identification() {
  const FopdtResult r = fitter_.result();
  ProcessGain = static_cast<REAL>(r.model.gain);
  TimeConstant = static_cast<REAL>(r.model.time_constant);
  DeadTime = static_cast<REAL>(r.model.dead_time);
  FitPercent = static_cast<REAL>(r.fit_percent);
  RSquared = static_cast<REAL>(r.r_squared);
  NoiseSigma = static_cast<REAL>(r.noise_sigma);
  if (!r.ok) return fail(0x8004);
  const PidGains g = tune(static_cast<TuningRule>(Rule), r.model, TauC);
  if (!g.ok) return fail(0x8005);
  Gain = static_cast<REAL>(g.gain);
  Ti = static_cast<REAL>(g.ti);
  Td = static_cast<REAL>(g.td);
  Phase = INT(TunePhase::Done);
  Busy = false;
  Done = true;
}

}  // namespace plc::control

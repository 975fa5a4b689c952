#include "plc/fb/weighing/batch_weigh.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace plc::weighing {

// Fine flow of this opening: a slope over the fine phase once the coarse
// tail has landed; the longer the window, the less quantisation noise.
void PR5510_BatchWeigh::measure_fine_rate(TIME now) {
  if (now - entered_ < FlowSettleTime) return;
  if (!rate_started_) {
    rate_started_ = true;
    rate_t1_ = now;
    rate_n1_ = ActualNet;
    return;
  }
  const double span = std::chrono::duration<double>(now - rate_t1_).count();
  if (span >= 0.2) {
    const auto r = static_cast<REAL>((ActualNet - rate_n1_) / span);
    if (r > 0) FineRate = r;
  }
}

// The net weight at which the fine valve closes.
REAL PR5510_BatchWeigh::cutoff() const {
  if (FlowCompensation && FineRate > 0 && time_learned_)
    return TargetWeight - std::min(InFlightTime * FineRate, FineSwitchPoint);
  return TargetWeight - PreactActual;
}

void PR5510_BatchWeigh::fail(std::uint16_t id, TIME now) {
  set_valves(false, false, false);
  Busy = false;
  Paused = false;
  Error = true;
  ErrorID = id;
  enter(BatchState::Error, now);
}

void PR5510_BatchWeigh::start(TIME now) {
  Done = Error = CommandAborted = false;
  ErrorID = error_id::kNone;
  const bool params_ok = TargetWeight > 0 && FineSwitchPoint >= 0 && Preact >= 0 && TolPlus >= 0 &&
                         TolMinus >= 0 && AdaptGain >= 0 && AdaptGain <= 1 &&
                         FineSwitchPoint < TargetWeight && MaxTopUps >= 0 &&
                         BelowZeroTime >= TIME::zero();
  if (Device == nullptr) return fail(error_id::kNoDevice, now);
  if (slot_ == PR5510_Device::kNoSlot) slot_ = Device->attach();
  if (slot_ == PR5510_Device::kNoSlot) return fail(error_id::kTooManyClients, now);
  if (!params_ok) return fail(error_id::kInvalidParameter, now);
  if (!learned_ || !AdaptPreact) {
    PreactActual = std::clamp(Preact, 0.0f, FineSwitchPoint);
    time_learned_ = false;
  }
  Busy = true;
  TopUps = 0;
  top_up_ = closed_by_preact_ = adapted_ = false;
  rate_started_ = false;
  FineRate = 0;
  ActualNet = 0;
  active_time_ = TIME::zero();
  below_zero_since_ = now;
  tare_step_ = TareStep::WaitReady;
  Device->ack_command(slot_);
  enter(BatchState::Tare, now);
}

void PR5510_BatchWeigh::finish_check(REAL final_net, TIME now) {
  const REAL dev = final_net - TargetWeight;
  if (!adapted_) {
    // Learn from the first check of a batch only, and only when the fine
    // valve was closed by the preact (a top-up or an overshoot in coarse
    // says nothing about the fine in-flight).
    LastDeviation = dev;
    if (AdaptPreact && closed_by_preact_) {
      const REAL step =
          std::clamp(AdaptGain * dev, -0.5f * FineSwitchPoint, 0.5f * FineSwitchPoint);
      if (FlowCompensation && FineRate > 0 && time_learned_) {
        InFlightTime = std::max(0.0f, InFlightTime + step / FineRate);
        PreactActual = std::min(InFlightTime * FineRate, FineSwitchPoint);
      } else {
        PreactActual = std::clamp(PreactActual + step, 0.0f, FineSwitchPoint);
      }
      learned_ = true;
    }
    adapted_ = true;
  }
  const REAL eps_under = 1e-5f * std::max(1.0f, std::abs(TargetWeight));
  if (dev < -TolMinus - eps_under && TopUps < MaxTopUps) {
    ++TopUps;
    top_up_ = true;
    top_up_len_ = TopUpPulse;
    if (FineRate > 0) {
      const auto want =
          std::chrono::duration_cast<TIME>(std::chrono::duration<double>(-dev / FineRate));
      top_up_len_ = std::clamp(want, TIME(std::chrono::milliseconds(kDeviceCycleMs)), TopUpPulse);
    }
    closed_by_preact_ = false;
    set_valves(false, true, false);
    enter(BatchState::Fine, now);
    return;
  }
  // Boundaries inclusive: a deviation of exactly the tolerance (a whole
  // number of display digits) must not fail on REAL rounding.
  const REAL eps = 1e-5f * std::max(1.0f, std::abs(TargetWeight));
  const bool in_tol = dev <= TolPlus + eps && dev >= -TolMinus - eps;
  LastNet = final_net;
  InTolerance = in_tol;
  LastResult = in_tol ? BatchResult::InTolerance
                      : (dev > 0 ? BatchResult::OverWeight : BatchResult::UnderWeight);
  ++BatchCount;
  TotalWeight += final_net;
  if (in_tol) {
    ++InTolCount;
  } else {
    ++OutTolCount;
  }
  if (!in_tol && StopOnOutOfTolerance)
    return fail(dev > 0 ? error_id::kOverWeight : error_id::kUnderWeight, now);
  if (DischargeEnable) {
    active_time_ = TIME::zero();
    enter(BatchState::Discharge, now);
  } else {
    Busy = false;
    Done = true;
    enter(BatchState::Done, now);
  }
}

}  // namespace plc::weighing

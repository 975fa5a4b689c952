#include "plc/fb/weighing/batch_weigh.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace plc::weighing {

namespace {
// weight_error()'s word: AduError, AboveFsd, Overload and BelowZero, one
// byte each, in a row.
static_assert(sizeof(bool) == 1);
static_assert(offsetof(StatusBits, AboveFsd) == offsetof(StatusBits, AduError) + 1);
static_assert(offsetof(StatusBits, Overload) == offsetof(StatusBits, AduError) + 2);
static_assert(offsetof(StatusBits, BelowZero) == offsetof(StatusBits, AduError) + 3);

constexpr auto kNetCode = static_cast<std::uint8_t>(ReadCode::Net);
// After the tare the net value needs a few device cycles (20 ms, spec §0)
// to show the new zero; sample the start weight after that.
constexpr TIME kSampleDelay = std::chrono::milliseconds(3 * kDeviceCycleMs);
constexpr TIME kReadyTimeout = std::chrono::seconds(2);
}  // namespace

void PR5510_BatchWeigh::set_valves(bool coarse, bool fine, bool discharge) {
  CoarseFeed = coarse;
  FineFeed = fine;
  Discharge = discharge;
  if (DriveDeviceOutputs && Device != nullptr) {
    // The three in one write of W[6], the byte three set_output() calls give.
    constexpr auto bit = [](OutputBit b) {
      return static_cast<std::uint8_t>(1U << static_cast<unsigned>(b));
    };
    constexpr std::uint8_t kValves =
        bit(OutputBit::Out1) | bit(OutputBit::Out2) | bit(OutputBit::Out3);
    Device->set_outputs(kValves, static_cast<std::uint8_t>((coarse ? bit(OutputBit::Out1) : 0) |
                                                           (fine ? bit(OutputBit::Out2) : 0) |
                                                           (discharge ? bit(OutputBit::Out3) : 0)));
  }
}

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

void PR5510_BatchWeigh::enter(BatchState s, TIME now) {
  State = s;
  entered_ = now;
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

void PR5510_BatchWeigh::operator()(const ScanContext& ctx) {
  const TIME now = ctx.now;
  const TIME dt = last_now_ == TIME::zero() ? TIME::zero() : now - last_now_;
  last_now_ = now;
  const bool rising = Execute && !prev_execute_;
  prev_execute_ = Execute;
  if (ResetTotals && !prev_reset_) {
    TotalWeight = 0;
    BatchCount = InTolCount = OutTolCount = 0;
    learned_ = false;
    time_learned_ = false;
    InFlightTime = 0;
    PreactActual = Preact;
  }
  prev_reset_ = ResetTotals;

  // PLCopen: Done / Error / CommandAborted held while Execute is TRUE, and
  // for one scan at least; then back to Idle. Execute asked first: TRUE
  // through a whole batch, it spares the three other tests.
  if (!Execute && (Done || Error || CommandAborted)) {
    Done = Error = CommandAborted = false;
    ErrorID = error_id::kNone;
    enter(BatchState::Idle, now);
  }
  if (rising && !Busy) start(now);
  if (!Busy) return;

  if (Abort) {
    set_valves(false, false, false);
    Busy = false;
    Paused = false;
    CommandAborted = true;
    enter(BatchState::Aborted, now);
    return;
  }
  // Device, slot_ and State read once: the device's byte stores below
  // (its request bits and codes) may alias them for the compiler, which
  // reloaded each; none of the device's calls writes this block.
  PR5510_Device* const dev = Device;
  if (dev == nullptr) return fail(error_id::kNoDevice, now);  // Busy set from outside
  if (!dev->Online) return fail(error_id::kDeviceOffline, now);
  const int slot = slot_;
  if (const std::uint16_t e = dev->read_error(slot); e != error_id::kNone) return fail(e, now);

  // The net weight, live through the read window (spec §3.5).
  if (dev->Ready && dev->read_valid(slot, kNetCode)) {
    net_ = dev->to_units(dev->read_dint());
    have_net_ = true;
  }
  // While a feed valve may open the cut-off needs every value: urgent.
  const BatchState state = State;
  const bool urgent = state == BatchState::Coarse || state == BatchState::Fine;
  dev->request_read(slot, kNetCode, urgent);
  if (state != BatchState::Tare) ActualNet = net_ - start_net_;

  if (!dev->status().BelowZero) below_zero_since_ = now;

  const bool feeding_state =
      state == BatchState::Coarse || state == BatchState::Fine || state == BatchState::Discharge;
  const bool was_paused = Paused;
  Paused = Pause && feeding_state;
  if (Paused) {
    set_valves(false, false, false);
    return;  // timers frozen: active_time_ does not advance
  }
  if (was_paused && state == BatchState::Fine && !top_up_) {
    // The flow stopped meanwhile: measure it afresh once it runs again
    // (FineRate keeps the last value until then).
    rate_started_ = false;
    entered_ = now;
  }
  if (feeding_state) active_time_ += dt;
  run_state(now, *dev, state);
}

// The weight this state acts on is not usable (0 = it is): read byte 7,
// spec §3.4 (manual §5.4), §7.2. Every busy state acts on the weight: Tare
// takes the start weight, Coarse..Check measure the fill, Discharge decides
// "empty". The header comment gives the rules.
std::uint16_t PR5510_BatchWeigh::weight_error(TIME now, const StatusBits& st,
                                              BatchState state) const {
  // None of the four bits below set, the usual scan: nothing to report. The
  // four are bools in a row (static_asserts below), tested as one word.
  std::uint32_t bits;
  std::memcpy(&bits, &st.AduError, sizeof bits);
  if (bits == 0) return error_id::kNone;
  // Adu Error, Over-load, Above FSD (the at/above-FSD half of Dimmed): the
  // value is invalid. Discharge goes on above FSD: the hopper must empty.
  const bool invalid =
      state == BatchState::Discharge ? st.AduError : st.AduError || st.Overload || st.AboveFsd;
  if (invalid) return error_id::kWeightInvalid;
  // Below Zero (the negative half of Dimmed) below the zero-set range: never
  // the flicker of an empty scale.
  if (st.BelowZero && !st.InsideZsr) return error_id::kBelowZero;
  // Held Below Zero while a fill is measured: the feed does not lift the
  // reading, not flicker either. At Check: a negative final weight.
  const bool measuring_fill = state == BatchState::Coarse || state == BatchState::Fine ||
                              state == BatchState::Settle ||
                              (state == BatchState::Tare && tare_step_ == TareStep::Sample);
  if (st.BelowZero &&
      (state == BatchState::Check || (measuring_fill && now - below_zero_since_ >= BelowZeroTime)))
    return error_id::kBelowZero;
  return error_id::kNone;
}

void PR5510_BatchWeigh::run_state(TIME now, PR5510_Device& dev, BatchState state) {
  const StatusBits& st = dev.status();
  if (const std::uint16_t e = weight_error(now, st, state); e != error_id::kNone)
    return fail(e, now);
  const bool filling = state == BatchState::Coarse || state == BatchState::Fine;
  if (filling && active_time_ > MaxFillTime) return fail(error_id::kFillTimeout, now);

  const auto coarse = [this, now] {
    if (ActualNet >= TargetWeight - PreactActual) {
      // Already at the cut-off: the coarse in-flight decides the rest.
      set_valves(false, false, false);
      enter(BatchState::Settle, now);
    } else if (ActualNet >= TargetWeight - FineSwitchPoint) {
      set_valves(false, true, false);
      enter(BatchState::Fine, now);
    } else {
      set_valves(true, true, false);
    }
  };
  // Coarse first: the coarse feed runs for most scans of a batch; one
  // compare takes them there, not the switch's bounds check and jump table
  // (the same step).
  if (state == BatchState::Coarse) [[likely]] {
    coarse();
    return;
  }
  switch (state) {
    case BatchState::Tare:
      set_valves(false, false, false);
      switch (tare_step_) {
        case TareStep::WaitReady:
          if (Device->Ready) {
            have_net_ = false;
            tare_step_ = TareAtStart ? TareStep::WaitStill : TareStep::Sample;
            entered_ = now;
          } else if (now - entered_ > kReadyTimeout) {
            fail(error_id::kNotReady, now);
          }
          break;
        case TareStep::WaitStill:
          // Spec §7.2: tare at standstill, or the device fails with error 31.
          if (st.StandStill) {
            Device->ack_command(slot_);
            Device->request_command(slot_, CommandBit::SetTare);
            tare_step_ = TareStep::Command;
          } else if (now - entered_ > MaxSettleTime) {
            fail(error_id::kSettleTimeout, now);
          }
          break;
        case TareStep::Command:
          if (Device->command_status(slot_) == CommandStatus::Done) {
            Device->ack_command(slot_);
            tare_step_ = TareStep::Sample;
            entered_ = now;
          } else if (Device->command_status(slot_) == CommandStatus::Error) {
            const std::uint16_t e = Device->command_error(slot_);
            Device->ack_command(slot_);
            fail(e, now);
          }
          break;
        case TareStep::Sample:
          if (have_net_ && now - entered_ >= kSampleDelay && Device->read_valid(slot_, kNetCode)) {
            start_net_ = net_;
            ActualNet = 0;
            active_time_ = TIME::zero();
            enter(BatchState::Coarse, now);
          }
          break;
      }
      break;

    case BatchState::Coarse:
      coarse();
      break;

    case BatchState::Fine:
      if (top_up_) {
        // A timed jog of the fine valve after an under-weight check.
        set_valves(false, true, false);
        if (now - entered_ >= top_up_len_) {
          set_valves(false, false, false);
          enter(BatchState::Settle, now);
        }
      } else {
        measure_fine_rate(now);
        if (FlowCompensation && FineRate > 0 && !time_learned_) {
          // First measured rate: turn the mass preact into a time.
          InFlightTime = PreactActual / FineRate;
          time_learned_ = true;
        }
        if (ActualNet >= cutoff()) {
          set_valves(false, false, false);
          closed_by_preact_ = true;
          enter(BatchState::Settle, now);
        } else {
          set_valves(false, true, false);
        }
      }
      break;

    case BatchState::Settle:
      set_valves(false, false, false);
      // The in-flight material lands during SettleTime; then the device
      // must report standstill with a net value that is ours (read_valid).
      if (now - entered_ >= SettleTime && st.StandStill && Device->read_valid(slot_, kNetCode)) {
        enter(BatchState::Check, now);
      } else if (now - entered_ > SettleTime + MaxSettleTime) {
        fail(error_id::kSettleTimeout, now);
      }
      break;

    case BatchState::Check:
      finish_check(ActualNet, now);
      break;

    case BatchState::Discharge:
      if (ActualNet <= EmptyWeight) {
        set_valves(false, false, false);
        Busy = false;
        Done = true;
        enter(BatchState::Done, now);
      } else if (active_time_ > MaxDischargeTime) {
        fail(error_id::kDischargeTimeout, now);
      } else {
        set_valves(false, false, true);
      }
      break;

    case BatchState::Idle:
    case BatchState::Done:
    case BatchState::Aborted:
    case BatchState::Error:
      break;
  }
}

}  // namespace plc::weighing

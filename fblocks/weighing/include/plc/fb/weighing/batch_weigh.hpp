// PR5510_BatchWeigh: one batch (dose) on a PR5510 scale: tare, coarse and
// fine feed, settle, check against the tolerance, discharge.
//
// The PR5510 manual defines no batching (spec §6), so, as on real lines,
// the batching runs in the PLC on top of the window protocol: the block
// reads the net weight (code 0x09) through the shared read window, tares
// with the W[7] Set Tare command, watches Stand-Still (R[7].6) and the
// range bits, and drives its valves on its Coarse/Fine/Discharge outputs;
// with DriveDeviceOutputs also on the PR5510's outputs 1/2/3 (W[6]).
// While a feed valve is open its net-weight read is urgent: it keeps the
// read window (PR5510_Device arbitration), so the cut-off sees every value.
//
// States (State output, enum value in brackets):
//   Idle(0) --Execute edge--> Tare(1) --> Coarse(2) --> Fine(3) --> Settle(4)
//   --> Check(5) --> Discharge(6) --> Done(7)
//   Check --under tolerance, top-ups left--> Fine (timed top-up pulse)
//   any busy state --Abort--> Aborted(8);  any fault --> Error(9).
// Feeding: Coarse opens the coarse AND the fine valve (two-speed feed) until
// the net reaches Target - FineSwitchPoint; Fine keeps the fine valve open
// until Target - PreactActual. PreactActual is the material still in flight
// (plus valve and measurement lag) when the valve closes; with AdaptPreact
// it learns from every batch: PreactActual += AdaptGain * (final - target),
// limited to [0, FineSwitchPoint] and to half a FineSwitchPoint per batch.
// FlowCompensation: the in-flight mass is proportional to the flow, and
// the flow changes from one valve opening to the next. So the block
// measures the fine flow of this batch (FineRate, from FlowSettleTime after
// the coarse valve closed) and learns the in-flight TIME instead:
// preact = InFlightTime * FineRate, InFlightTime += AdaptGain * deviation /
// FineRate. Until a rate is measured it uses PreactActual as a mass.
// An under-weight batch is topped up with fine pulses of
// shortfall / FineRate (at most TopUpPulse).
//
// Recovery (documented contract):
//  * Done, Aborted, Error: all valves closed at once. Done, Error and
//    CommandAborted are held while Execute stays TRUE (at least one scan);
//    when they drop the block returns to Idle. A new rising edge of Execute
//    starts a fresh batch from Tare: with TareAtStart the material left on
//    the scale is tared off, otherwise the batch is measured from the net
//    weight at its start. An aborted batch is not counted in the totals.
//  * Pause (level) closes the valves in Coarse, Fine and Discharge and
//    freezes the fill / discharge timers; Pause FALSE resumes in the same
//    state (material that landed meanwhile counts; the fine flow is
//    measured afresh). Other states run on.
//  * Errors: device offline / read timeouts (16#80xx), tare refused
//    (16#81nn device error), MaxFillTime (16#8202), no standstill within
//    MaxSettleTime (16#8203), weight invalid: Adu Error, Over-load or above
//    full scale (16#8204; spec §7.2 "weight invalid"; in Discharge only Adu
//    Error, since an over-full hopper must still be emptied), discharge
//    timeout (16#8205), out of tolerance with StopOnOutOfTolerance (16#8206
//    over, 16#8207 under: the batch is counted, not discharged, and waits
//    for the operator), weight clearly below zero (16#8209, see below).
//    Each stops feeding at once (all valves closed), and a batch that has
//    not reached Check is not counted.
//  * Below zero (spec §3.4 = manual §5.4, read byte 7): Below Zero (bit 3,
//    gross <= -1/4 d) is the negative half of Dimmed (bit 7). A weight is
//    clearly below zero, and the batch fails with 16#8209, when
//      - Below Zero is set while Inside ZSR (bit 5) is off: the gross is
//        below the device's zero-set range, the zero band; in every state,
//        from Tare to Discharge; or
//      - Below Zero stays set for BelowZeroTime without a break while the
//        block measures a fill (from the sample after the tare through
//        Coarse, Fine and Settle): the feed does not lift the reading; or
//      - Below Zero is set at Check: a final weight that reads negative is
//        never counted.
//    Any other Below Zero inside the zero band is the flicker of an empty
//    scale around zero, or a zero a few digits low, and is tolerated (at
//    the tare, at the start of the feed until the material lands, at the
//    end of the discharge). A W&M device refuses the tare of a negative
//    weight itself (error 33, 16#8121).
// Totals: ResetTotals (rising edge) clears totals, counts and the learned
// preact.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "plc/fb/weighing/pr5510_device.hpp"

namespace plc::weighing {

enum class BatchState : std::uint8_t {
  Idle = 0,
  Tare = 1,
  Coarse = 2,
  Fine = 3,
  Settle = 4,
  Check = 5,
  Discharge = 6,
  Done = 7,
  Aborted = 8,
  Error = 9,
};

enum class BatchResult : std::uint8_t {
  None = 0,
  InTolerance = 1,
  OverWeight = 2,
  UnderWeight = 3
};

class PR5510_BatchWeigh {
 public:
  PR5510_Device* Device = nullptr;

  // ---- inputs (weights in display units, e.g. kg) ----
  BOOL Execute{};
  BOOL Abort{};
  BOOL Pause{};
  REAL TargetWeight{};
  REAL FineSwitchPoint{};  // coarse closes this much before the target
  REAL Preact{};           // initial in-flight estimate
  BOOL AdaptPreact = true;
  REAL AdaptGain = 0.5f;
  REAL TolPlus{};
  REAL TolMinus{};
  TIME SettleTime = std::chrono::milliseconds(500);  // after the valve closed, then standstill
  TIME MaxSettleTime = std::chrono::seconds(5);
  TIME MaxFillTime = std::chrono::seconds(60);
  BOOL TareAtStart = true;
  BOOL DischargeEnable = true;
  REAL EmptyWeight{};  // discharge ends at or below this net weight
  TIME MaxDischargeTime = std::chrono::seconds(30);
  BOOL StopOnOutOfTolerance{};
  INT MaxTopUps = 2;
  TIME TopUpPulse = std::chrono::milliseconds(200);
  BOOL FlowCompensation = true;
  TIME FlowSettleTime = std::chrono::milliseconds(600);  // coarse tail still landing
  BOOL DriveDeviceOutputs = true;                        // valves on PR5510 outputs 1/2/3 too
  BOOL ResetTotals{};
  // Below Zero held this long while measuring a fill is not flicker (16#8209);
  // longer than the fall time of the first material onto a scale whose zero
  // is a little low, and than the flicker of a vibrating empty scale.
  TIME BelowZeroTime = std::chrono::seconds(1);

  // ---- outputs ----
  BOOL CoarseFeed{};
  BOOL FineFeed{};
  BOOL Discharge{};
  BatchState State = BatchState::Idle;
  REAL ActualNet{};  // net since the start of this batch
  REAL LastNet{};    // final net of the last checked batch
  BatchResult LastResult = BatchResult::None;
  BOOL InTolerance{};
  REAL LastDeviation{};  // final - target of the last batch (before top-ups)
  REAL PreactActual{};   // in-flight mass in use (learned)
  REAL InFlightTime{};   // learned in-flight time, s (FlowCompensation)
  REAL FineRate{};       // fine flow of this batch, units/s (0 = not measured)
  LREAL TotalWeight{};
  DINT BatchCount{};
  DINT InTolCount{};
  DINT OutTolCount{};
  INT TopUps{};
  BOOL Busy{};
  BOOL Done{};
  BOOL Error{};
  BOOL CommandAborted{};
  BOOL Paused{};
  WORD ErrorID{};

  PLC_REFLECT(Execute, Abort, Pause, TargetWeight, FineSwitchPoint, Preact, AdaptPreact, AdaptGain,
              TolPlus, TolMinus, SettleTime, MaxSettleTime, MaxFillTime, TareAtStart,
              DischargeEnable, EmptyWeight, MaxDischargeTime, StopOnOutOfTolerance, MaxTopUps,
              TopUpPulse, FlowCompensation, FlowSettleTime, DriveDeviceOutputs, ResetTotals,
              BelowZeroTime, CoarseFeed, FineFeed, Discharge, State, ActualNet, LastNet, LastResult,
              InTolerance, LastDeviation, PreactActual, InFlightTime, FineRate, TotalWeight,
              BatchCount, InTolCount, OutTolCount, TopUps, Busy, Done, Error, CommandAborted,
              Paused, ErrorID,
              // internal state: shown by the debugger, kept in recording snapshots
              slot_, prev_execute_, prev_reset_, learned_, have_net_, closed_by_preact_, top_up_,
              adapted_, tare_step_, net_, start_net_, entered_, active_time_, last_now_,
              rate_started_, time_learned_, rate_t1_, rate_n1_, top_up_len_, below_zero_since_)
  // State too: the state machine runs on it.
  PLC_INTERNAL(State, slot_, prev_execute_, prev_reset_, learned_, have_net_, closed_by_preact_,
               top_up_, adapted_, tare_step_, net_, start_net_, entered_, active_time_, last_now_,
               rate_started_, time_learned_, rate_t1_, rate_n1_, top_up_len_, below_zero_since_)
  // Kept over a warm start (fblocks/weighing/README.md "Retain"): what the
  // block learned (the preact and in-flight time, and that it learned them),
  // the totals and counts, and the ResetTotals edge memory (a reset held
  // through a power cut does not clear the totals again).
  PLC_RETAIN(PreactActual, InFlightTime, learned_, time_learned_, TotalWeight, BatchCount,
             InTolCount, OutTolCount, prev_reset_)

  // Inline (defined below, with run_state()): the programs' cycle() takes
  // the batch's scan without a call, its register saves and frame; the rare
  // steps (start(), fail(), finish_check(), the fine rate) stay out of line.
  inline void operator()(const ScanContext& ctx);

 private:
  enum class TareStep : std::uint8_t { WaitReady, WaitStill, Command, Sample };

  static constexpr auto kNetCode = static_cast<std::uint8_t>(ReadCode::Net);
  // After the tare the net value needs a few device cycles (20 ms, spec §0)
  // to show the new zero; sample the start weight after that.
  static constexpr TIME kSampleDelay = std::chrono::milliseconds(3 * kDeviceCycleMs);
  static constexpr TIME kReadyTimeout = std::chrono::seconds(2);

  void start(TIME now);
  inline void enter(BatchState s, TIME now);
  void fail(std::uint16_t id, TIME now);
  void finish_check(REAL final_net, TIME now);
  // Called from operator() alone (weight_error() from run_state()), every
  // scan while busy: inline, no call and no register saves. With what
  // operator() has read already (ctx.now, *Device, State: none of them
  // written since), not loaded again.
  [[gnu::always_inline]] inline void run_state(TIME now, PR5510_Device& dev, BatchState state);
  // Every busy scan sets the valves: inline.
  [[gnu::always_inline]] inline void set_valves(bool coarse, bool fine, bool discharge);
  void measure_fine_rate(TIME now);
  [[gnu::always_inline]] [[nodiscard]] inline std::uint16_t weight_error(TIME now,
                                                                         const StatusBits& st,
                                                                         BatchState state) const;
  [[nodiscard]] REAL cutoff() const;

  int slot_ = PR5510_Device::kNoSlot;
  bool prev_execute_ = false, prev_reset_ = false, learned_ = false;
  bool have_net_ = false, closed_by_preact_ = false, top_up_ = false, adapted_ = false;
  TareStep tare_step_ = TareStep::WaitReady;
  REAL net_ = 0.0f, start_net_ = 0.0f;
  TIME entered_{};      // when the current state (or step) began
  TIME active_time_{};  // fill or discharge time, frozen while paused
  TIME last_now_{};
  // fine flow measurement
  bool rate_started_ = false, time_learned_ = false;
  TIME rate_t1_{};
  REAL rate_n1_ = 0.0f;
  TIME top_up_len_{};
  TIME below_zero_since_{};  // last scan without Below Zero (R[7].3)
};

// weight_error()'s word: AduError, AboveFsd, Overload and BelowZero, one
// byte each, in a row.
static_assert(sizeof(bool) == 1);
static_assert(offsetof(StatusBits, AboveFsd) == offsetof(StatusBits, AduError) + 1);
static_assert(offsetof(StatusBits, Overload) == offsetof(StatusBits, AduError) + 2);
static_assert(offsetof(StatusBits, BelowZero) == offsetof(StatusBits, AduError) + 3);

inline void PR5510_BatchWeigh::set_valves(bool coarse, bool fine, bool discharge) {
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

inline void PR5510_BatchWeigh::enter(BatchState s, TIME now) {
  State = s;
  entered_ = now;
}

// The weight this state acts on is not usable (0 = it is): read byte 7,
// spec §3.4 (manual §5.4), §7.2. Every busy state acts on the weight: Tare
// takes the start weight, Coarse..Check measure the fill, Discharge decides
// "empty". The header comment gives the rules.
inline std::uint16_t PR5510_BatchWeigh::weight_error(TIME now, const StatusBits& st,
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

inline void PR5510_BatchWeigh::run_state(TIME now, PR5510_Device& dev, BatchState state) {
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

inline void PR5510_BatchWeigh::operator()(const ScanContext& ctx) {
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

}  // namespace plc::weighing

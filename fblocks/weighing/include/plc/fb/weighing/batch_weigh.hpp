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

  void operator()(const ScanContext& ctx);

 private:
  enum class TareStep : std::uint8_t { WaitReady, WaitStill, Command, Sample };

  void start(TIME now);
  void enter(BatchState s, TIME now);
  void fail(std::uint16_t id, TIME now);
  void finish_check(REAL final_net, TIME now);
  // Called from operator() alone (weight_error() from run_state()), every
  // scan while busy: inline, no call and no register saves. With what
  // operator() has read already (ctx.now, *Device, State: none of them
  // written since), not loaded again.
  [[gnu::always_inline]] inline void run_state(TIME now, PR5510_Device& dev, BatchState state);
  // Every busy scan sets the valves: inline (defined in batch_weigh.cpp).
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

}  // namespace plc::weighing

// CONT_C: the continuous controller of the S7-300/400 "Standard PID
// Control" library (FB 41), with its interface and defaults (Siemens
// function manual "PID control", A5E35300227, "CONT_C" under "PID basic
// functions"), for programs ported from it. Percent in, percent out.
//
// Signal path, as the manual's block diagram draws it:
//   PV = PVPER_ON ? (PV_PER x 100 / 27648) x PV_FAC + PV_OFF : PV_IN
//   ER = dead_band(SP_INT - PV, DEADB_W)
//   LMN_P = P_SEL ? GAIN x ER : 0
//   LMN_I = I_SEL ? integral of GAIN x ER / TI : 0
//   LMN_D = D_SEL ? lagged_derivative(GAIN x ER, TD, TM_LAG) : 0
//   LMN = limit(MAN_ON ? MAN : LMN_P + LMN_I + LMN_D + DISV, LMN_LLM, LMN_HLM)
//         x LMN_FAC + LMN_OFF
//   LMN_PER = LMN x 27648 / 100
// The P, I and D actions are in parallel and GAIN acts on all three (the
// manual's form), unlike PID_Compact, where Kp multiplies the I and D
// parts of the ideal form.
//
// Readings (fblocks/control/README.md has the reasons):
// * The process value normalisation (PV_FAC, PV_OFF) applies to PV_PER
//   only, as the diagram places PV_NORM after CRP_IN.
// * The dead band is the shifted one: 0 inside +-DEADB_W, ER -+ DEADB_W
//   outside (continuous at the band's edges).
// * The integral is integrated with the time CYCLE (the manual's sampling
//   time: the block trusts it is called every CYCLE, as on an S7). CYCLE =
//   T#0s is our extension: the measured time since the previous call.
//   TI below CYCLE counts as CYCLE.
// * Anti-windup: the integral stops while LMN sits at a limit and the error
//   would drive it further (the manual: the integral action is held at the
//   limits); INT_HOLD holds it always; I_ITL_ON sets it to I_ITLVAL.
// * In manual mode (MAN_ON) the integral tracks LMN - LMN_P - DISV and the
//   derivative is 0, so the switch to automatic is bumpless (the manual
//   says so for MAN_ON).
// * COM_RST: a complete restart: the integral (I_ITLVAL with I_ITL_ON, else
//   0), the derivative and every output go to 0 for that call.
#pragma once

#include "plc/fb/control/lagged_derivative.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::control {

struct CONT_C {
  // ---------------- inputs (defaults as in the manual's table) ----------------
  BOOL COM_RST{};
  BOOL MAN_ON = true;
  BOOL PVPER_ON{};
  BOOL P_SEL = true;
  BOOL I_SEL = true;
  BOOL INT_HOLD{};
  BOOL I_ITL_ON{};
  BOOL D_SEL{};
  TIME CYCLE = std::chrono::seconds(1);
  REAL SP_INT{};
  REAL PV_IN{};
  WORD PV_PER{};
  REAL MAN{};
  REAL GAIN = 2.0f;
  TIME TI = std::chrono::seconds(20);
  TIME TD = std::chrono::seconds(10);
  TIME TM_LAG = std::chrono::seconds(2);
  REAL DEADB_W{};
  REAL LMN_HLM = 100.0f;
  REAL LMN_LLM = 0.0f;
  REAL PV_FAC = 1.0f;
  REAL PV_OFF{};
  REAL LMN_FAC = 1.0f;
  REAL LMN_OFF{};
  REAL I_ITLVAL{};
  REAL DISV{};

  // ---------------- outputs ----------------
  REAL LMN{};
  WORD LMN_PER{};
  BOOL QLMN_HLM{};
  BOOL QLMN_LLM{};
  REAL LMN_P{};
  REAL LMN_I{};
  REAL LMN_D{};
  REAL PV{};
  REAL ER{};

  void operator()(const ScanContext& ctx);

  // ---------------- internal ----------------
  LREAL integral_{};
  LaggedDerivative derivative_;
  TIME last_call_{};
  BOOL called_{};

  PLC_REFLECT(COM_RST, MAN_ON, PVPER_ON, P_SEL, I_SEL, INT_HOLD, I_ITL_ON, D_SEL, CYCLE, SP_INT,
              PV_IN, PV_PER, MAN, GAIN, TI, TD, TM_LAG, DEADB_W, LMN_HLM, LMN_LLM, PV_FAC, PV_OFF,
              LMN_FAC, LMN_OFF, I_ITLVAL, DISV, LMN, LMN_PER, QLMN_HLM, QLMN_LLM, LMN_P, LMN_I,
              LMN_D, PV, ER, integral_, derivative_, last_call_, called_)
  PLC_INTERNAL(integral_, derivative_, last_call_, called_)
};

}  // namespace plc::control

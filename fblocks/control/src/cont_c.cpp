#include "plc/fb/control/cont_c.hpp"

#include <algorithm>
#include <cmath>

namespace plc::control {
namespace {

double seconds(TIME t) { return std::chrono::duration<double>(t).count(); }

double dead_band(double er, double width) {
  if (width <= 0) return er;
  if (er > width) return er - width;
  if (er < -width) return er + width;
  return 0;
}

}  // namespace

void CONT_C::operator()(const ScanContext& ctx) {
  const double measured = called_ ? seconds(ctx.now - last_call_) : seconds(ctx.period);
  last_call_ = ctx.now;
  called_ = true;
  const double h = CYCLE > TIME(0) ? seconds(CYCLE) : measured;

  // Process value and error.
  double pv = PV_IN;
  if (PVPER_ON) {
    const double raw = static_cast<std::int16_t>(std::uint16_t(PV_PER));
    pv = raw * 100.0 / 27648.0 * double(PV_FAC) + double(PV_OFF);
  }
  PV = static_cast<REAL>(pv);
  const double er = dead_band(double(SP_INT) - pv, DEADB_W);
  ER = static_cast<REAL>(er);
  const double gain_er = double(GAIN) * er;

  if (COM_RST) {
    integral_ = I_ITL_ON ? double(I_ITLVAL) : 0.0;
    derivative_.reset(gain_er);
    LMN = LMN_P = LMN_D = 0;
    LMN_I = static_cast<REAL>(integral_);
    LMN_PER = 0;
    QLMN_HLM = QLMN_LLM = false;
    return;
  }

  const double lmn_p = P_SEL ? gain_er : 0.0;
  const double disv = DISV;
  const double hlm = LMN_HLM, llm = LMN_LLM;
  double lmn_d = 0;
  if (D_SEL && h > 0 && !MAN_ON) {
    lmn_d = derivative_.step(gain_er, h, seconds(TD), seconds(TM_LAG));
  } else {
    derivative_.reset(gain_er);
  }

  double lmn = 0;
  if (MAN_ON) {
    lmn = std::clamp(double(MAN), std::min(llm, hlm), std::max(llm, hlm));
    // Tracking: the switch to automatic continues from this output.
    integral_ = I_SEL ? lmn - lmn_p - disv : 0.0;
  } else {
    if (!I_SEL) {
      integral_ = 0;
    } else if (I_ITL_ON) {
      integral_ = I_ITLVAL;
    } else if (!INT_HOLD && h > 0) {
      const double ti = std::max(seconds(TI), h);
      const double di = gain_er * h / ti;
      const double unlimited = lmn_p + integral_ + di + lmn_d + disv;
      if (!((unlimited > hlm && di > 0) || (unlimited < llm && di < 0))) integral_ += di;
    }
    lmn = lmn_p + integral_ + lmn_d + disv;
  }
  QLMN_HLM = lmn >= hlm;
  QLMN_LLM = lmn <= llm;
  lmn = std::clamp(lmn, std::min(llm, hlm), std::max(llm, hlm));
  lmn = lmn * double(LMN_FAC) + double(LMN_OFF);
  LMN = static_cast<REAL>(lmn);
  LMN_P = static_cast<REAL>(lmn_p);
  LMN_I = static_cast<REAL>(integral_);
  LMN_D = static_cast<REAL>(lmn_d);
  const double per = std::clamp(std::round(lmn * 27648.0 / 100.0), -32768.0, 32767.0);
  LMN_PER = static_cast<std::uint16_t>(static_cast<std::int16_t>(per));
}

}  // namespace plc::control

// Counters CTU, CTD, CTUD (IEC 61131-3 ed.3 6.6.3.5.4 Table 45 / ed.2
// 2.5.2.3.3 Table 36), written as the standard's ST bodies:
//
//   CTU:  IF R THEN CV := 0; ELSIF CU AND (CV < PVmax) THEN CV := CV+1; END_IF;
//         Q := (CV >= PV);
//   CTD:  IF LD THEN CV := PV; ELSIF CD AND (CV > PVmin) THEN CV := CV-1; END_IF;
//         Q := (CV <= 0);
//   CTUD: IF R THEN CV := 0; ELSIF LD THEN CV := PV;
//         ELSIF NOT (CU AND CD) THEN
//           IF CU AND (CV < PVmax) THEN CV := CV+1;
//           ELSIF CD AND (CV > PVmin) THEN CV := CV-1; END_IF;
//         END_IF;
//         QU := (CV >= PV); QD := (CV <= 0);
//
// CU and CD are R_EDGE inputs: an implicit R_TRIG (memory initially FALSE)
// that is evaluated on every call, also while R or LD hold the counter. So a
// first call with CU = TRUE counts. PVmax/PVmin are the limits of the counter
// type: CV saturates there and never wraps. R has priority over LD.
//
// The bodies compute the count step without branching on the (often
// changing) count inputs: CV + (edge AND CV < PVmax) equals the IF chain
// above, but costs no branch misprediction per call.
//
// CTU/CTD/CTUD count in INT as in ed.2; ed.3's typed variants are the
// aliases CTU_INT, CTU_DINT, CTU_LINT, CTU_UDINT, CTU_ULINT (same for CTD,
// CTUD).
#pragma once

#include <limits>

#include "plc/reflect.hpp"
#include "plc/types.hpp"

namespace plc::iec {

template <class T>
struct CTU_T {
  T PV{};           // input: preset value
  T CV{};           // output: current value, 0..max of T
  BOOL CU{};        // input, rising edge counts
  BOOL R{};         // input: reset to 0 (level)
  BOOL Q{};         // output: CV >= PV
  BOOL cu_prev_{};  // CU of the previous call (R_EDGE memory)

  void operator()() {
    const bool up = CU & !cu_prev_ & (CV < std::numeric_limits<T>::max());
    cu_prev_ = CU;
    CV = R ? T{0} : T(CV + T(up));
    Q = CV >= PV;
  }

  // IEC-style call: CTU1(CU := x, R := r, PV := 10); returns Q.
  BOOL operator()(BOOL cu, BOOL r, T pv) {
    CU = cu;
    R = r;
    PV = pv;
    (*this)();
    return Q;
  }

  PLC_REFLECT(CU, R, PV, Q, CV, cu_prev_)
  PLC_INTERNAL(cu_prev_)
};

template <class T>
struct CTD_T {
  T PV{};           // input: value loaded by LD
  T CV{};           // output: current value, min of T..
  BOOL CD{};        // input, rising edge counts down
  BOOL LD{};        // input: load PV (level)
  BOOL Q{};         // output: CV <= 0
  BOOL cd_prev_{};  // CD of the previous call (R_EDGE memory)

  void operator()() {
    const bool down = CD & !cd_prev_ & (CV > std::numeric_limits<T>::min());
    cd_prev_ = CD;
    CV = LD ? PV : T(CV - T(down));
    Q = CV <= T{0};
  }

  // IEC-style call: CTD1(CD := x, LD := ld, PV := 10); returns Q.
  BOOL operator()(BOOL cd, BOOL ld, T pv) {
    CD = cd;
    LD = ld;
    PV = pv;
    (*this)();
    return Q;
  }

  PLC_REFLECT(CD, LD, PV, Q, CV, cd_prev_)
  PLC_INTERNAL(cd_prev_)
};

template <class T>
struct CTUD_T {
  T PV{};           // input: preset value (QU threshold, loaded by LD)
  T CV{};           // output: current value
  BOOL CU{};        // input, rising edge counts up
  BOOL CD{};        // input, rising edge counts down
  BOOL R{};         // input: reset to 0, priority over LD
  BOOL LD{};        // input: load PV
  BOOL QU{};        // output: CV >= PV
  BOOL QD{};        // output: CV <= 0
  BOOL cu_prev_{};  // R_EDGE memories
  BOOL cd_prev_{};

  void operator()() {
    const bool cu_edge = CU & !cu_prev_;
    const bool cd_edge = CD & !cd_prev_;
    cu_prev_ = CU;
    cd_prev_ = CD;
    // Both edges at once: no count (NOT (CU AND CD) in the standard).
    const bool up = cu_edge & !cd_edge & (CV < std::numeric_limits<T>::max());
    const bool down = cd_edge & !cu_edge & (CV > std::numeric_limits<T>::min());
    CV = R ? T{0} : LD ? PV : T(CV + T(up) - T(down));
    QU = CV >= PV;
    QD = CV <= T{0};
  }

  // IEC-style call: CTUD1(CU := u, CD := d, R := r, LD := ld, PV := 10).
  void operator()(BOOL cu, BOOL cd, BOOL r, BOOL ld, T pv) {
    CU = cu;
    CD = cd;
    R = r;
    LD = ld;
    PV = pv;
    (*this)();
  }

  PLC_REFLECT(CU, CD, R, LD, PV, QU, QD, CV, cu_prev_, cd_prev_)
  PLC_INTERNAL(cu_prev_, cd_prev_)
};

using CTU = CTU_T<INT>;
using CTD = CTD_T<INT>;
using CTUD = CTUD_T<INT>;
using CTU_INT = CTU_T<INT>;
using CTD_INT = CTD_T<INT>;
using CTUD_INT = CTUD_T<INT>;
using CTU_DINT = CTU_T<DINT>;
using CTD_DINT = CTD_T<DINT>;
using CTUD_DINT = CTUD_T<DINT>;
using CTU_LINT = CTU_T<LINT>;
using CTD_LINT = CTD_T<LINT>;
using CTUD_LINT = CTUD_T<LINT>;
using CTU_UDINT = CTU_T<UDINT>;
using CTD_UDINT = CTD_T<UDINT>;
using CTUD_UDINT = CTUD_T<UDINT>;
using CTU_ULINT = CTU_T<ULINT>;
using CTD_ULINT = CTD_T<ULINT>;
using CTUD_ULINT = CTUD_T<ULINT>;

}  // namespace plc::iec

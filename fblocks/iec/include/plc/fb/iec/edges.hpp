// Edge detection, R_TRIG and F_TRIG (IEC 61131-3 ed.3 6.6.3.5.3 Table 44 /
// ed.2 2.5.2.3.2 Table 35), written exactly as the standard's ST bodies:
//
//   R_TRIG: Q := CLK AND NOT M;      M := CLK;
//   F_TRIG: Q := NOT CLK AND NOT M;  M := NOT CLK;
//
// with M initially FALSE. Consequences that follow from the standard text and
// are kept on purpose (tests pin them):
// * R_TRIG: a first call with CLK = TRUE gives Q = TRUE (CLK is taken to have
//   been FALSE before the first scan).
// * F_TRIG: a first call with CLK = FALSE gives Q = TRUE (M = FALSE means
//   "CLK was TRUE"), like matiec/OpenPLC. Programs that must not see this
//   startup pulse preset M = TRUE or ignore Q on the first scan.
//
// The bodies use & and | on BOOL instead of && and ||: same result, but no
// branch on CLK, which costs a misprediction per call on changing inputs.
#pragma once

#include "plc/reflect.hpp"
#include "plc/types.hpp"

namespace plc::iec {

struct R_TRIG {
  BOOL CLK{};  // input
  BOOL Q{};    // output: TRUE for one call after CLK rose
  BOOL M{};    // internal: CLK of the previous call (IEC name)

  void operator()() {
    Q = CLK & !M;
    M = CLK;
  }

  // IEC-style call with input: R_TRIG1(CLK := x); returns Q.
  BOOL operator()(BOOL clk) {
    CLK = clk;
    (*this)();
    return Q;
  }

  PLC_REFLECT(CLK, Q, M)
  PLC_INTERNAL(M)
};

struct F_TRIG {
  BOOL CLK{};  // input
  BOOL Q{};    // output: TRUE for one call after CLK fell
  BOOL M{};    // internal: NOT CLK of the previous call (IEC name)

  void operator()() {
    Q = !CLK & !M;
    M = !CLK;
  }

  // IEC-style call with input: F_TRIG1(CLK := x); returns Q.
  BOOL operator()(BOOL clk) {
    CLK = clk;
    (*this)();
    return Q;
  }

  PLC_REFLECT(CLK, Q, M)
  PLC_INTERNAL(M)
};

}  // namespace plc::iec

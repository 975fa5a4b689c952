// Bistables SR and RS (IEC 61131-3 ed.3 6.6.3.5.2 Table 43 / ed.2 2.5.2.3.1
// Table 34), as the standard's ST bodies:
//
//   SR (set dominant):   Q1 := S1 OR (NOT R AND Q1);
//   RS (reset dominant): Q1 := NOT R1 AND (S OR Q1);
//
// Q1 is both output and state (initially FALSE); nothing else is stored.
// & and | instead of && and ||: same result without branches on the inputs.
#pragma once

#include "plc/reflect.hpp"
#include "plc/types.hpp"

namespace plc::iec {

struct SR {
  BOOL S1{};  // input: set, dominant
  BOOL R{};   // input: reset
  BOOL Q1{};  // output and state

  void operator()() { Q1 = S1 | (!R & Q1); }

  // IEC-style call: SR1(S1 := s, R := r); returns Q1.
  BOOL operator()(BOOL s1, BOOL r) {
    S1 = s1;
    R = r;
    (*this)();
    return Q1;
  }

  PLC_REFLECT(S1, R, Q1)
};

struct RS {
  BOOL S{};   // input: set
  BOOL R1{};  // input: reset, dominant
  BOOL Q1{};  // output and state

  void operator()() { Q1 = (!R1) & (S | Q1); }

  // IEC-style call: RS1(S := s, R1 := r); returns Q1.
  BOOL operator()(BOOL s, BOOL r1) {
    S = s;
    R1 = r1;
    (*this)();
    return Q1;
  }

  PLC_REFLECT(S, R1, Q1)
};

}  // namespace plc::iec

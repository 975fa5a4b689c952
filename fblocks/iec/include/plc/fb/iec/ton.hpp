// TON, on-delay timer (IEC 61131-3 ed.3 6.6.3.5.5 Table 46 / ed.2 2.5.2.3.4
// Tables 37-38): Q rises PT after IN rose and stays TRUE while IN stays TRUE;
// ET runs from 0 to PT and is clamped there; IN = FALSE resets Q and ET.
//
// Readings where the standard leaves the behaviour to the implementation
// (ed.3 Table 46 note: "the effect of a change in the value of PT during the
// timing operation is implementation-specific"), chosen like CODESYS/matiec:
// * The timer is evaluated at the scan time of each call, including the call
//   that sees the rising edge, so PT = T#0s gives Q = TRUE on that same scan.
// * A PT change before expiry takes effect at once (elapsed time compared with
//   the new PT; a PT below the elapsed time expires the timer immediately).
// * After expiry Q is latched until IN falls and ET keeps the PT it expired
//   with: a later PT change does not switch Q off again.
// * A negative PT counts as T#0s.
#pragma once

#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::iec {

struct TON {
  // Declared 8-byte fields first, flags last: 32 bytes per instance instead
  // of 48 with IEC order (cache footprint of large arrays of timers).
  // Reflection (debugger order) follows the IEC order, see PLC_REFLECT.
  TIME PT{};        // input: preset time
  TIME ET{};        // output: elapsed time, 0..PT
  TIME start_{};    // scan time of the rising edge of IN
  BOOL IN{};        // input
  BOOL Q{};         // output
  BOOL running_{};  // IN was TRUE on the previous call (start_ is valid)

  // Plain branches, on purpose: with slowly changing IN per instance (the
  // usual case, and the DESIGN.md reference workload) they predict well and
  // the common paths exit early. Measured alternative (bench_iec_fb, not
  // kept): a mask-based branch-free body is about 3x faster when the IN
  // values of the instances in one loop are random (each branch on IN then
  // mispredicts half the time) but about 2x slower on predictable inputs.
  // GCC turns `?:` on TIME back into branches, so only masks avoid them.
  void operator()(const ScanContext& ctx) {
    if (!IN) {
      Q = false;
      ET = TIME{};
      running_ = false;
      return;
    }
    if (!running_) {
      running_ = true;
      start_ = ctx.now;
    }
    if (Q) return;  // expired: latched until IN falls
    const TIME elapsed = ctx.now - start_;
    if (elapsed >= PT) {
      Q = true;
      ET = PT < TIME{} ? TIME{} : PT;
    } else {
      ET = elapsed;
    }
  }

  // IEC-style call with inputs: TON1(IN := x, PT := T#20ms); returns Q.
  BOOL operator()(const ScanContext& ctx, BOOL in, TIME pt) {
    IN = in;
    PT = pt;
    (*this)(ctx);
    return Q;
  }

  PLC_REFLECT(IN, PT, Q, ET, start_, running_)
  PLC_INTERNAL(start_, running_)
};

}  // namespace plc::iec

// TOF, off-delay timer (IEC 61131-3 ed.3 6.6.3.5.5 Table 46 / ed.2 2.5.2.3.4
// Tables 37-38): Q is TRUE while IN is TRUE and stays TRUE for PT after IN
// falls; ET runs from 0 to PT after the falling edge, is clamped at PT and
// held there until IN rises again; IN = TRUE resets ET to 0.
//
// Readings where the standard leaves the behaviour to the implementation
// (PT change during timing is implementation-specific, ed.3 Table 46 note),
// chosen like CODESYS/matiec:
// * Evaluated at the scan time of each call: PT = T#0s drops Q on the scan
//   that sees the falling edge.
// * A PT change before expiry takes effect at once; after expiry Q stays
//   FALSE (latched) until IN rises, whatever PT becomes.
// * Initial state: Q = FALSE, ET = 0; a first call with IN = FALSE is not a
//   falling edge (nothing was switched on).
// * A negative PT counts as T#0s.
#pragma once

#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::iec {

struct TOF {
  // 8-byte fields first, flags last (32 bytes per instance); reflection in
  // IEC order.
  TIME PT{};        // input: preset time
  TIME ET{};        // output: elapsed time since the falling edge, 0..PT
  TIME start_{};    // scan time of the falling edge of IN
  BOOL IN{};        // input
  BOOL Q{};         // output
  BOOL prev_in_{};  // IN on the previous call (falling-edge detection)

  void operator()(const ScanContext& ctx) {
    if (IN) {
      Q = true;
      ET = TIME{};
      prev_in_ = true;
      return;
    }
    if (prev_in_) {  // falling edge: the off-delay starts now
      prev_in_ = false;
      start_ = ctx.now;
    }
    if (!Q) return;  // idle or expired: ET holds its value until IN rises
    const TIME elapsed = ctx.now - start_;
    if (elapsed >= PT) {
      Q = false;
      ET = PT < TIME{} ? TIME{} : PT;
    } else {
      ET = elapsed;
    }
  }

  // IEC-style call with inputs: TOF1(IN := x, PT := T#1s); returns Q.
  BOOL operator()(const ScanContext& ctx, BOOL in, TIME pt) {
    IN = in;
    PT = pt;
    (*this)(ctx);
    return Q;
  }

  PLC_REFLECT(IN, PT, Q, ET, start_, prev_in_)
  PLC_INTERNAL(start_, prev_in_)
};

}  // namespace plc::iec

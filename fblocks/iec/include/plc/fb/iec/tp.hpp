// TP, pulse timer (IEC 61131-3 ed.3 6.6.3.5.5 Table 46 / ed.2 2.5.2.3.4
// Tables 37-38): a rising edge of IN starts a pulse Q of length PT. The
// pulse is not retriggerable: edges during the pulse are ignored and the
// pulse runs its full PT even if IN falls. A new pulse needs a rising edge
// of IN after the pulse ended. ET runs 0..PT during the pulse; after the
// pulse it holds PT while IN stays TRUE and is 0 once IN is FALSE.
//
// Readings where the standard leaves the behaviour to the implementation:
// * Q is TRUE on the scans with start <= now < start + PT, evaluated at each
//   call's scan time: PT = T#0s gives no pulse at all (Q stays FALSE), and a
//   rising edge on the very scan where a pulse ends starts the next pulse.
// * A PT change during the pulse takes effect at once; setting PT to T#0s
//   ends the pulse (the use the ed.3 Table 46 note mentions).
// * A negative PT counts as T#0s.
#pragma once

#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::iec {

struct TP {
  // 8-byte fields first, flags last (32 bytes per instance); reflection in
  // IEC order.
  TIME PT{};        // input: pulse length
  TIME ET{};        // output: elapsed pulse time, 0..PT
  TIME start_{};    // scan time at which the current pulse started
  BOOL IN{};        // input
  BOOL Q{};         // output: the pulse (TRUE exactly while a pulse runs)
  BOOL prev_in_{};  // IN on the previous call (rising-edge detection)

  void operator()(const ScanContext& ctx) {
    const bool rising = IN && !prev_in_;
    prev_in_ = IN;
    if (Q) {  // pulse running: edges are ignored, only the time counts
      const TIME elapsed = ctx.now - start_;
      if (elapsed >= PT) {
        Q = false;
        ET = PT < TIME{} ? TIME{} : PT;
      } else {
        ET = elapsed;
        return;
      }
    }
    if (rising) {  // no pulse running (or it ended at this very scan)
      start_ = ctx.now;
      ET = TIME{};
      Q = PT > TIME{};
      return;
    }
    if (!IN) ET = TIME{};
  }

  // IEC-style call with inputs: TP1(IN := x, PT := T#500ms); returns Q.
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

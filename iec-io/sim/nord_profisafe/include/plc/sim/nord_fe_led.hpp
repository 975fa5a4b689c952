// The red "FE" (failsafe error) LED blink code of the NORD bus interface
// (spec nord-profisafe.md §5.6): it shows the last two digits of the 57xx
// code. One cycle: strobe of 3 pulses (200 ms on / 200 ms off), 2 s off,
// the tens digit as N blinks (1 s on / 1 s off), the units digit likewise.
// [AMBIG] The gap between the digit groups and after the units is not in the
// text (the figure is missing): we use 2 s off for both, and a digit 0 gives
// no blinks.
#pragma once

#include <chrono>
#include <cstdint>

#include "plc/types.hpp"

namespace plc::sim {

// LED state at time `t` after the code appeared; off for code 0.
inline bool nord_fe_led(std::uint16_t code, TIME t) {
  using std::chrono::milliseconds;
  if (code == 0) return false;
  const int tens = (code / 10) % 10;
  const int units = code % 10;
  const std::int64_t strobe = 3 * 400, pause = 2000, blink = 2000;
  const std::int64_t cycle = strobe + pause + tens * blink + pause + units * blink + pause;
  std::int64_t ms = std::chrono::duration_cast<milliseconds>(t).count() % cycle;
  if (ms < strobe) return (ms % 400) < 200;
  ms -= strobe + pause;
  if (ms < 0) return false;
  if (ms < tens * blink) return (ms % blink) < 1000;
  ms -= tens * blink + pause;
  if (ms < 0) return false;
  if (ms < units * blink) return (ms % blink) < 1000;
  return false;
}

}  // namespace plc::sim

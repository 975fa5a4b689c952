// LCM's time stamp convention (the utime fields of every message, the
// transports' receive times, plcctl's command counters): the wall clock in
// microseconds since the Unix epoch. A wall clock, not the scan's clock: the
// readers are operators' tools and log files on other machines, which compare
// it with their own wall clocks.
#pragma once

#include <chrono>
#include <cstdint>

namespace plc::hmi {

inline std::int64_t utime_now() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace plc::hmi

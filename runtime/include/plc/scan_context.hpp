// What every FB sees of its scan: the task's timestamp, period and count.
//
// Time comes from the task, never from the system clock: in virtual time
// `now` advances exactly one period per scan, in real time it is the
// scheduled release time of the scan (not the wake-up time), so FB timing
// does not pick up wake-up jitter.
#pragma once

#include <cstdint>

#include "plc/types.hpp"

namespace plc {

struct ScanContext {
  TIME now{};             // release time of this scan since runtime start
  TIME period{};          // the task's period
  std::uint64_t cycle{};  // scans of this task so far (0 for the first)
};

}  // namespace plc

// Per-task timing statistics: scan (execution) time and wake latency as
// histograms, plus overruns and skipped releases.
#pragma once

#include <cstdint>
#include <string>

#include "plc/histogram.hpp"

namespace plc {

struct TaskStats {
  Histogram scan_ns;     // time from scan start to scan end (latch..publish)
  Histogram latency_ns;  // real time only: wake-up time minus release time
  std::uint64_t scans = 0;
  std::uint64_t overruns = 0;  // scans that ended after their next release
  std::uint64_t skipped = 0;   // releases dropped because of overruns
  bool watchdog_tripped = false;
  bool faulted = false;     // stopped by an exception from a program
  std::string stop_reason;  // why the task stopped early ("" = it did not)
};

}  // namespace plc

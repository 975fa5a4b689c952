// The real-time overrun policy as a pure function (tested without a clock).
//
// Releases lie on the grid t0 + k*period. After the scan of release k ended
// at `done`, the next release is k+1, unless that is already in the past:
// then it is an overrun, every release in the past is skipped (counted, not
// run), and the task continues with the first release after `done`. Missed
// cycles are never run back to back, and the IEC time base stays on the grid.
#pragma once

#include <cstdint>

namespace plc {

struct NextRelease {
  std::int64_t index = 0;     // k of the next release
  std::uint64_t skipped = 0;  // releases dropped
  bool overrun = false;
};

inline NextRelease next_release(std::int64_t k, std::int64_t t0, std::int64_t period,
                                std::int64_t done) {
  NextRelease r{k + 1, 0, false};
  if (t0 + r.index * period <= done) {
    const std::int64_t first_future = (done - t0) / period + 1;
    r.overrun = true;
    r.skipped = static_cast<std::uint64_t>(first_future - r.index);
    r.index = first_future;
  }
  return r;
}

}  // namespace plc

// The side channel of the reload kill test (test_retain_reload_crash.cpp):
// a shared file mapping (MAP_SHARED survives the SIGKILL) in which the
// ReloadProbe programs (reload_probe.cpp, a cell library built in two
// versions) note what happened. The test reads it after the kill.
#pragma once

#include <atomic>
#include <cstdint>

namespace retaintest {

struct ReloadChannel {
  struct Slot {                         // one per program (its `slot` field)
    std::atomic<std::int64_t> last{0};  // count after its latest scan
  };
  Slot slots[2];
  std::atomic<std::int64_t> started{0};      // 1 once slot 0 scanned
  std::atomic<std::int64_t> constructed{0};  // program objects built (start, reload)
  std::atomic<std::int64_t> new_scans{0};    // scans of version 2's code
};

}  // namespace retaintest

// CrashProbe: a retained counter that grows by one every scan, and a side
// channel the crash test reads after a SIGKILL: a shared file mapping
// (MAP_SHARED survives the process) that holds, per scan, the count just
// reached, and at the first scan the count the start-up restored. Set up
// in init() (outside the scans); a scan only stores into mapped memory.
#pragma once

#include <atomic>
#include <cstdint>

#include "plc/program.hpp"

namespace retaintest {

struct ProbeChannel {
  std::atomic<std::int64_t> last{0};      // count after the latest scan
  std::atomic<std::int64_t> restored{0};  // count at the start of the first scan
  std::atomic<std::int64_t> started{0};   // 1 once the first scan ran
};

class CrashProbe : public plc::ProgramBase<CrashProbe> {
 public:
  plc::LINT counter = 0;
  void init() override;
  void cycle(const plc::ScanContext&) override;
  PLC_REFLECT(counter)
  PLC_RETAIN(counter)

 private:
  ProbeChannel* ch_ = nullptr;
  bool first_ = true;
};

}  // namespace retaintest

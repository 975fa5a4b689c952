#include "crash_probe.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdlib>

namespace retaintest {

void CrashProbe::init() {
  const char* file = std::getenv("PLC_RETAIN_PROBE_FILE");
  if (!file) return;
  const int fd = ::open(file, O_RDWR | O_CREAT, 0644);
  if (fd < 0) return;
  if (::ftruncate(fd, sizeof(ProbeChannel)) == 0) {
    void* p = ::mmap(nullptr, sizeof(ProbeChannel), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (p != MAP_FAILED) ch_ = static_cast<ProbeChannel*>(p);
  }
  ::close(fd);
}

void CrashProbe::cycle(const plc::ScanContext&) {
  if (first_ && ch_) {
    ch_->restored.store(counter, std::memory_order_relaxed);
    ch_->started.store(1, std::memory_order_release);
  }
  first_ = false;
  ++counter;
  if (ch_) ch_->last.store(counter, std::memory_order_release);
}

PLC_REGISTER_PROGRAM(CrashProbe)

}  // namespace retaintest

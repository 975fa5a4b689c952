// ReloadProbe: a retained counter whose retain layout changes between two
// builds (RELOAD_PROBE_VERSION), for the reload kill test. Every scan ends
// with values that only one scan of one build can leave:
//   1  count, gone = 3 * count, twin = count       (offsets 0, 8, 16)
//   2  count, added = 5 * count, pad = -count, twin = count
//                                                  (offsets 0, 8, 16, 24)
// so a retain copy that mixed two scans, or one layout's header with the
// other's values, breaks an equation. The channel (reload_probe.hpp) is
// mapped in the constructor: the reload constructs the new build's programs
// on the console thread, outside any scan; a scan only stores into it.
#include "reload_probe.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdlib>

#include "plc/program.hpp"

using namespace plc;

namespace {

retaintest::ReloadChannel* map_channel() {
  const char* file = std::getenv("PLC_RELOAD_PROBE_FILE");
  if (!file) return nullptr;
  const int fd = ::open(file, O_RDWR | O_CREAT, 0644);
  if (fd < 0) return nullptr;
  void* p = MAP_FAILED;
  if (::ftruncate(fd, sizeof(retaintest::ReloadChannel)) == 0)
    p = ::mmap(nullptr, sizeof(retaintest::ReloadChannel), PROT_READ | PROT_WRITE, MAP_SHARED, fd,
               0);
  ::close(fd);
  return p == MAP_FAILED ? nullptr : static_cast<retaintest::ReloadChannel*>(p);
}

}  // namespace

class ReloadProbe : public ProgramBase<ReloadProbe> {
 public:
  LINT count = 0;
#if RELOAD_PROBE_VERSION == 1
  LINT gone = -1;
#else
  LINT added = -1;
  LINT pad = 1;
#endif
  LINT twin = 0;
  DINT slot = 0;  // which channel slot (config init:); not retained

  ReloadProbe() : ch_(map_channel()) {
    if (ch_) ch_->constructed.fetch_add(1, std::memory_order_relaxed);
  }
  ~ReloadProbe() override {
    if (ch_) ::munmap(ch_, sizeof *ch_);
  }

  void cycle(const ScanContext&) override {
    retaintest::ReloadChannel::Slot* s = ch_ && slot >= 0 && slot < 2 ? &ch_->slots[slot] : nullptr;
#if RELOAD_PROBE_VERSION == 1
    if (ch_ && slot == 0) ch_->started.store(1, std::memory_order_release);
#else
    if (ch_ && slot == 0) ch_->new_scans.fetch_add(1, std::memory_order_relaxed);
#endif
    ++count;
#if RELOAD_PROBE_VERSION == 1
    gone = 3 * count;
#else
    added = 5 * count;
    pad = -count;
#endif
    twin = count;
    if (s) s->last.store(count, std::memory_order_release);
  }

#if RELOAD_PROBE_VERSION == 1
  PLC_REFLECT(count, gone, twin, slot)
  PLC_RETAIN(count, gone, twin)
#else
  PLC_REFLECT(count, added, pad, twin, slot)
  PLC_RETAIN(count, added, pad, twin)
#endif

 private:
  retaintest::ReloadChannel* ch_;
};
PLC_REGISTER_PROGRAM(ReloadProbe)

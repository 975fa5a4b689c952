// plchmi: the HMI bridge's process (hmi-bridge/README.md, "Process
// layout"). plcrun starts it with the shared memory and the doorbell as
// inherited descriptors, unprivileged, and starts it again when it dies:
//   plchmi --state-fd 3 --control-fd 4 --doorbell-fd 5
// It ends on SIGTERM or SIGINT (exit 0). Exit 78 (EX_CONFIG): it cannot
// start (the url cannot be opened, the shared memory is not plcrun's);
// 2: bad usage.
#include <signal.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "plc/hmi/bridge.hpp"

namespace {

std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free);  // so async-signal-safe

extern "C" void on_signal(int) { g_stop.store(true); }

int usage() {
  std::fprintf(stderr,
               "usage: plchmi --state-fd N --control-fd N [--doorbell-fd N]\n"
               "(plcrun starts it for a cell with an hmi: section)\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  int state = -1, control = -1, doorbell = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return usage();
    char* end = nullptr;
    const long fd = std::strtol(argv[++i], &end, 10);
    if (*end || fd < 0 || fd > 1024) return usage();
    if (a == "--state-fd")
      state = int(fd);
    else if (a == "--control-fd")
      control = int(fd);
    else if (a == "--doorbell-fd")
      doorbell = int(fd);
    else
      return usage();
  }
  if (state < 0 || control < 0) return usage();
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);
  try {
    std::string err;
    auto regions = plc::hmi::ipc::Regions::attach(state, control, err);
    if (!regions) {
      std::fprintf(stderr, "plchmi: %s\n", err.c_str());
      return 78;
    }
    plc::hmi::Bridge bridge(std::move(regions), doorbell);
    bridge.publish_description();
    bridge.run(g_stop);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "plchmi: %s\n", e.what());
    return 78;
  }
  return 0;
}

// Fuzz target: the HMI bridge's command decoding and handling
// (Bridge::on_command_bytes) and plcrun's serving of the record it makes
// (Host::round, through the shared memory, both halves in lockstep) on the
// filling cell in virtual time, over memq://. The first byte picks the bridge: one with a shared
// key (nothing the fuzzer sends can carry a right HMAC tag, so no command may ever be applied:
// traps if one is) or one without (writes and forces only where the patterns allow; stopping
// commands refused). The keyed bridge's epoch is random (command_auth.hpp), so a fuzzed command
// cannot carry a tag for it even by replaying a seed's bytes. The rest, at most 64 kB (one LCM
// datagram), is the message. Every input is counted as malformed, refused
// (access, bad tag, stale epoch, replay) or applied, never a crash.
#include <sys/stat.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "fuzz_hmi_host.hpp"
#include "plc/hmi/bridge.hpp"

namespace {

plc::CellConfig session_config(bool keyed) {
  plc::CellConfig cfg = plc::fuzz::filling_cell_with_hmi();
  cfg.hmi.writable.push_back({"Cell.pitch", {}});
  if (keyed) {
    cfg.hmi.key_path = "/tmp/plc_fuzz_hmi_" + std::to_string(::getpid()) + ".key";
    std::ofstream(cfg.hmi.key_path)
        << "5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a5a\n";
    ::chmod(cfg.hmi.key_path.c_str(), 0600);  // load_key refuses a key others may read
  }
  return cfg;
}

struct Session {
  plc::fuzz::LockstepHmiHost cell;
  std::unique_ptr<plc::hmi::Bridge> bridge;
  explicit Session(bool keyed) : cell(session_config(keyed)) {
    bridge = std::make_unique<plc::hmi::Bridge>(cell.host->regions().view());
    bridge->set_peer([this] { cell.host->round(); });
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1 || size > 65536 + 1) return 0;
  static Session open(false), keyed(true);
  Session& s = (data[0] & 1) ? keyed : open;
  const auto before = s.bridge->counters();
  s.bridge->on_command_bytes(data + 1, size - 1);
  s.bridge->service();  // plcrun serves what went through the ring; its reply comes back
  const auto after = s.bridge->counters();
  const std::uint64_t counted =
      (after.malformed - before.malformed) + (after.refused - before.refused) +
      (after.bad_tag - before.bad_tag) + (after.replayed - before.replayed) +
      (after.stale - before.stale) + (after.commands - before.commands);
  // "describe" is answered without being counted; everything else once.
  if (counted > 1) __builtin_trap();
  if (&s == &keyed && after.commands != 0) __builtin_trap();
  return 0;
}

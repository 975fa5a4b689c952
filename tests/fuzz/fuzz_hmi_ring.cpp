// Fuzz target: plcrun's side of the HMI's command ring (Host::round and
// check_record, plc/hmi/host_commands.hpp) fed records that no bridge would
// write: what a plchmi taken over by an attacker could put into the shared
// memory. The filling cell in virtual time, its host in lockstep, no bridge:
// the input's bytes are the record (zero-filled or cut to its size); when
// the first byte's low bit is set, the record's generation is made the
// current one, so that the checks after it are reached. Every record gets
// exactly one reply with its token and a known reason; nothing crashes, and
// no variable the cell's hmi: patterns do not allow is ever written or
// forced (traps otherwise).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>

#include "fuzz_hmi_host.hpp"

namespace {

plc::CellConfig session_config() {
  plc::CellConfig cfg = plc::fuzz::filling_cell_with_hmi();
  // Off: a step of up to 1,000,000 scans per input would slow the
  // fuzzer down to nothing; the stop verbs are then refused (NoStops).
  cfg.hmi.stop_commands.value = false;
  return cfg;
}

struct Session {
  plc::fuzz::LockstepHmiHost cell{session_config()};
  std::unique_ptr<plc::hmi::ipc::Regions> bridge_side = cell.host->regions().view();
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static Session s;
  static auto rec = std::make_unique<plc::hmi::ipc::CommandRecord>();
  static auto reply = std::make_unique<plc::hmi::ipc::ReplyRecord>();
  std::memset(static_cast<void*>(rec.get()), 0, sizeof *rec);
  std::memcpy(static_cast<void*>(rec.get()), data + 1,
              std::min(size - 1, sizeof(plc::hmi::ipc::CommandRecord)));
  if (data[0] & 1)
    rec->generation = s.bridge_side->state().generation.load(std::memory_order_acquire);
  static std::uint32_t token = 0;
  rec->token = ++token;
  if (!s.bridge_side->commands().push(*rec)) __builtin_trap();  // one at a time: never full
  s.cell.host->round();
  auto replies = s.bridge_side->replies();
  if (replies.pop(*reply) != decltype(replies)::Pop::Got) __builtin_trap();
  if (reply->token != token || reply->reason >= plc::hmi::ipc::kReasons) __builtin_trap();
  for (const auto& name : s.cell.dbg->forced())
    if (name != "Cell.run") __builtin_trap();
  if (s.cell.dbg->forced().size() > 1) __builtin_trap();
  return 0;
}

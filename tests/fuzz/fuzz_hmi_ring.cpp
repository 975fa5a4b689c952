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

#include "fuzz_cell.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/hmi/host.hpp"

namespace {

struct Session {
  plc::CellConfig cfg;
  std::unique_ptr<plc::hmi::Host> host;
  std::unique_ptr<plc::debug::Debugger> dbg;
  std::unique_ptr<plc::hmi::ipc::Regions> bridge_side;
  Session() {
    cfg = plc::fuzz::filling_cell();
    cfg.hmi.present = true;
    cfg.hmi.url.value = "memq://";
    cfg.hmi.publish = {{"Cell.*", {}}};
    cfg.hmi.writable = {{"Cell.target_kg", {}}};
    cfg.hmi.forceable = {{"Cell.run", {}}};
    // Off: a step of up to 1,000,000 scans per input would slow the
    // fuzzer down to nothing; the stop verbs are then refused (NoStops).
    cfg.hmi.stop_commands.value = false;
    plc::hmi::Host::Options ho;
    ho.mode = plc::hmi::Host::Mode::Lockstep;
    host = std::make_unique<plc::hmi::Host>(cfg.hmi, cfg.file, ho);
    plc::debug::Debugger::Options o;
    o.span = std::chrono::seconds(1);
    o.on_build = [this](plc::Runtime& rt) { host->attach(rt); };
    dbg = std::make_unique<plc::debug::Debugger>(
        [this] { return std::make_unique<plc::Runtime>(cfg); }, o);
    host->set_debugger(dbg.get());
    bridge_side = host->regions().view();
  }
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
  s.host->round();
  auto replies = s.bridge_side->replies();
  if (replies.pop(*reply) != decltype(replies)::Pop::Got) __builtin_trap();
  if (reply->token != token || reply->reason >= plc::hmi::ipc::kReasons) __builtin_trap();
  for (const auto& name : s.dbg->forced())
    if (name != "Cell.run") __builtin_trap();
  if (s.dbg->forced().size() > 1) __builtin_trap();
  return 0;
}

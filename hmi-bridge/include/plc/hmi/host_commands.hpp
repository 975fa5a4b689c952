// plcrun's check of a command record from the bridge's process (the
// command ring, plc/hmi/ipc/records.hpp): every field against plcrun's own
// cell layout, before the debugger sees anything. A record the bridge (or
// whatever wrote into the ring) got wrong is refused with a Reason and a
// sentence; nothing in it is text, so nothing is parsed. The access the
// layout gives (writable, forceable, stop_commands) is checked here again,
// by index, whatever the bridge checked: a bridge process that was taken
// over cannot write what the cell's hmi: patterns do not allow.
// tests/fuzz/fuzz_hmi_ring.cpp feeds this random records.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "plc/debug/condition_code.hpp"
#include "plc/hmi/ipc/cell_layout.hpp"
#include "plc/hmi/ipc/records.hpp"

namespace plc::hmi {

// A variable of the layout, or an address inside the image.
struct HostTarget {
  std::optional<std::uint32_t> var;
  std::optional<io::IecAddress> address;
};

struct HostCommand {
  ipc::Verb verb = ipc::Verb::None;
  std::uint32_t token = 0;
  bool restore = false;
  std::uint64_t count = 0;  // Step: scans (1..kMaxStep); Break: hits; Delete: id
  HostTarget target;        // Write, Force, Unforce: always a variable of the layout
  alignas(8) unsigned char value[8] = {};
  std::vector<HostTarget> operands;  // Read: what to read; Break: the code's operands
  debug::ConditionCode code;         // Break: validated (condition_code.hpp validate())
};

struct RecordCheck {
  std::optional<HostCommand> command;  // set when the record may be served
  ipc::Reason reason = ipc::Reason::Ok;
  std::string why;  // for a refusal
};

// Checks `r` against `layout` of generation `generation`, the cell's
// stop_commands.
RecordCheck check_record(const ipc::CommandRecord& r, const ipc::CellLayout& layout,
                         std::uint64_t generation, bool stop_commands);

}  // namespace plc::hmi

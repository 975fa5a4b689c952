// The bridge's picture of one generation of the cell (a build of plcrun's
// runtime): the layout plcrun wrote, what the bridge derived from it, and
// per task where its snapshot stands. Private to hmi-bridge/src/bridge/.
#pragma once

#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "plc/hmi/bridge.hpp"
#include "plc/hmi/ipc/cell_layout.hpp"
#include "plc/hmi/ipc/records.hpp"
#include "softplc_hmi/cell_description_t.hpp"

namespace plc::hmi {

struct Bridge::View {
  std::uint64_t generation = 0;
  ipc::CellLayout cell;
  std::map<std::string, std::uint32_t> index;  // path -> cell.vars
  softplc_hmi::cell_description_t desc;
  struct Slot {
    std::uint64_t requested = 0;  // what this bridge wrote into requests[k]
    bool waiting = false;         // asked, not filled yet
    std::chrono::steady_clock::time_point asked{};
    std::chrono::steady_clock::duration fast_for{};  // poll closely this long after asking
    std::chrono::steady_clock::time_point last_full{};
    std::vector<std::string> last;  // per item: the text last sent
  };
  std::vector<Slot> slots;
  // What the bridge last reported of each device (publish_device_alarms).
  struct DeviceSeen {
    std::uint64_t changes = 0;
    std::uint8_t state = 0;  // io::DeviceState
    bool ever_online = false;
  };
  std::vector<DeviceSeen> devices;
  bool devices_known = false;  // set from the first diagnostics note
};

// A command that went to plcrun, until its reply comes.
struct Bridge::Pending {
  std::int64_t request_id = 0;
  std::string client;
  ipc::Verb verb = ipc::Verb::None;
  // Read: per name asked, its index into the record's operands (-1: the
  // bridge already knew the error), with the error or the layout variable.
  std::vector<std::string> names;
  std::vector<int> operand;
  std::vector<std::string> errors;
  std::vector<std::string> addresses;  // of what was read ("" when none)
  std::chrono::steady_clock::time_point sent{};
};

}  // namespace plc::hmi

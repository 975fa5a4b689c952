// What plcrun's HMI host refreshes in the shared memory between scans, for
// the bridge to publish: task statistics, device health with each device's
// last state change (for device alarms), and the bridge's own outages
// (plchmi died; the host noted when and how). Each is a seqlock block
// (seqlock.hpp) in the encoding of wire.hpp.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace plc::hmi::ipc {

struct StatsNote {
  struct Task {
    std::uint64_t scans = 0, overruns = 0, skipped = 0;
    std::int64_t scan_ns_min = 0, scan_ns_avg = 0, scan_ns_max = 0;
    std::string stop_reason;
  };
  std::vector<Task> tasks;  // in the layout's task order
  [[nodiscard]] std::vector<unsigned char> encode() const;
  static std::optional<StatsNote> decode(const std::vector<unsigned char>& b);
};

struct DiagNote {
  struct Device {
    std::uint8_t live_state = 0;  // io::DeviceState, the plugin's present state
    std::uint8_t seen_state = 0;  // io::DeviceState as the device's task's scans see it
    // DeviceLink::last_change()
    std::uint64_t changes = 0;
    std::uint8_t from = 0, to = 0;
    bool torn = false;
    std::uint64_t scan = 0;
    std::int64_t time_ns = 0;
    std::string diagnostics;  // the plugin's own text
  };
  std::vector<Device> devices;  // in the layout's device order
  [[nodiscard]] std::vector<unsigned char> encode() const;
  static std::optional<DiagNote> decode(const std::vector<unsigned char>& b);
};

// The bridge process's outages, newest last.
struct OutageNote {
  struct Outage {
    std::uint64_t number = 0;     // 1 = the first since plcrun started
    std::string cause;            // "exited (signal 11)", "exited with status 3"
    std::int64_t down_utime = 0;  // CLOCK_REALTIME, microseconds
    std::int64_t up_utime = 0;    // 0 while it is still down
  };
  static constexpr std::size_t kKept = 8;
  std::uint64_t total = 0;
  std::vector<Outage> recent;  // at most kKept
  [[nodiscard]] std::vector<unsigned char> encode() const;
  static std::optional<OutageNote> decode(const std::vector<unsigned char>& b);
};

}  // namespace plc::hmi::ipc

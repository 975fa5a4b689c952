// What plcrun tells its HMI bridge about the cell it runs, once per build
// of the runtime: tasks, devices, every variable with the access the cell's
// `hmi:` patterns give it (resolved by plcrun, which has the registry), and
// where each task's published values land in the shared memory. The bridge
// builds its cell_description_t from it, finds variables by path in it, and
// hands plcrun indices into it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "plc/io/iec_address.hpp"
#include "plc/types.hpp"

namespace plc::hmi::ipc {

struct CellLayout {
  struct Task {
    std::string name;
    std::int64_t period_ns = 0;
    friend bool operator==(const Task&, const Task&) = default;
  };
  struct Device {
    std::string name, plugin, input, output;  // input/output: IEC address of the first byte
    std::int32_t task = -1;
    std::int32_t in_bytes = 0, out_bytes = 0;
    friend bool operator==(const Device&, const Device&) = default;
  };
  struct Var {
    std::string path;
    VarType type = VarType::BOOL;
    std::optional<io::IecAddress> address;
    std::int32_t task = -1;  // -1: an address of no task
    bool published = false, writable = false, forceable = false, read_only = false;
    friend bool operator==(const Var&, const Var&) = default;
  };
  // One published value in its task's snapshot buffer.
  struct Item {
    std::uint32_t var = 0;     // index into vars
    std::uint32_t offset = 0;  // in the buffer
    friend bool operator==(const Item&, const Item&) = default;
  };
  // A task's snapshot: SlotHeader at `header`, values at `buffer` (offsets
  // in the state region).
  struct Slot {
    std::uint32_t task = 0;
    std::uint64_t header = 0, buffer = 0, buffer_size = 0;
    std::vector<Item> items;
    friend bool operator==(const Slot&, const Slot&) = default;
  };

  // An alarm that holds for the whole run, noted by plcrun at start-up
  // (kind `retain_cold_start`: a warm start that fell back to a cold one).
  struct Alarm {
    std::string kind, source, text;
    std::int64_t utime = 0;  // CLOCK_REALTIME, microseconds
    friend bool operator==(const Alarm&, const Alarm&) = default;
  };

  std::string cell;
  std::uint64_t layout_hash = 0;                                      // Runtime::layout_hash()
  std::uint32_t image_input = 0, image_output = 0, image_memory = 0;  // bytes
  std::vector<Task> tasks;
  std::vector<Device> devices;
  std::vector<Var> vars;
  std::vector<Slot> slots;
  std::vector<Alarm> start_alarms;

  [[nodiscard]] std::vector<unsigned char> encode() const;
  // Checks every count and string, the types and address enums, the
  // indices (a variable's task, an item's variable) and that each slot lies
  // within `region_size` bytes; nullopt and `error` otherwise.
  static std::optional<CellLayout> decode(const unsigned char* p, std::size_t n,
                                          std::size_t region_size, std::string& error);
  // The index of `path` in vars (linear; the bridge keeps a map).
  [[nodiscard]] std::optional<std::uint32_t> find(const std::string& path) const;
  // Whether `a` lies inside the image (every byte of it).
  [[nodiscard]] bool inside_image(const io::IecAddress& a) const;
  friend bool operator==(const CellLayout&, const CellLayout&) = default;
};

inline constexpr std::uint8_t kVarTypes = std::uint8_t(VarType::STRING) + 1;

}  // namespace plc::hmi::ipc

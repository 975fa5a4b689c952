// The state and control regions (layout.hpp) as one side maps them, with
// typed access to their parts. plcrun creates them (Regions::create) for a
// cell layout; plchmi maps the inherited descriptors (Regions::attach) and
// checks what it finds before it uses anything; in one process (tests,
// benchmarks) Regions::view gives the bridge the same memory the way
// plchmi would see it.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "plc/hmi/ipc/cell_layout.hpp"
#include "plc/hmi/ipc/layout.hpp"
#include "plc/hmi/ipc/notes.hpp"
#include "plc/hmi/ipc/records.hpp"
#include "plc/hmi/ipc/ring.hpp"
#include "plc/hmi/ipc/seqlock.hpp"
#include "plc/hmi/ipc/shared_memory.hpp"

namespace plc::hmi::ipc {

// Bytes of the blocks plcrun refreshes, per task and per device.
inline constexpr std::size_t kStatsPerTask = 640;
inline constexpr std::size_t kDiagPerDevice = 2112;
inline constexpr std::size_t kMaxDiagnosticsText = 2048;
inline constexpr std::size_t kMaxStopReason = 512;

class Regions {
 public:
  // Places the layout's slots (SlotHeader, then the buffer of each, whose
  // buffer_size the caller has set), sizes both regions, creates them,
  // writes the headers, the settings and the layout (generation 2), asks
  // for every task's first snapshot, and seals the state region. Throws
  // std::system_error.
  static std::unique_ptr<Regions> create(const Settings& settings, CellLayout& layout,
                                         std::uint64_t boot_epoch);
  // Maps inherited descriptors and checks magic, version and that every
  // section lies inside its region; nullptr and `error` otherwise.
  static std::unique_ptr<Regions> attach(int state_fd, int control_fd, std::string& error);
  // The bridge's view of regions this process created (in-process bridge).
  [[nodiscard]] std::unique_ptr<Regions> view() const;

  // Whether `layout` (slots placed the same way) fits these regions as they
  // are: same slot count and sections. Then rewrite() may reuse them.
  [[nodiscard]] bool fits(CellLayout& layout) const;
  // plcrun, on a rebuilt runtime: generation odd, the new layout written,
  // first snapshots asked for, generation even again.
  void rewrite(const CellLayout& layout);
  // The layout as plcrun wrote it, decoded and checked (the bridge), with
  // the generation it belongs to; nullopt while plcrun rewrites it.
  [[nodiscard]] std::optional<CellLayout> read_layout(std::uint64_t& generation,
                                                      std::string& error) const;

  [[nodiscard]] StateHeader& state() const { return *reinterpret_cast<StateHeader*>(state_); }
  [[nodiscard]] ControlHeader& control() const {
    return *reinterpret_cast<ControlHeader*>(control_);
  }
  [[nodiscard]] const Settings& settings() const {
    return *reinterpret_cast<const Settings*>(state_ + state().settings.offset);
  }
  [[nodiscard]] SlotHeader& slot_header(const CellLayout::Slot& s) const {
    return *reinterpret_cast<SlotHeader*>(state_ + s.header);
  }
  [[nodiscard]] unsigned char* slot_buffer(const CellLayout::Slot& s) const {
    return state_ + s.buffer;
  }
  [[nodiscard]] SeqBlock stats() const { return block(state().stats); }
  [[nodiscard]] SeqBlock diag() const { return block(state().diag); }
  [[nodiscard]] SeqBlock outages() const { return block(state().outages); }
  [[nodiscard]] Ring<CommandRecord> commands() const;
  [[nodiscard]] Ring<ReplyRecord> replies() const;

  [[nodiscard]] int state_fd() const { return state_map_.fd(); }
  [[nodiscard]] int control_fd() const { return control_map_.fd(); }
  [[nodiscard]] std::size_t state_size() const { return state_size_; }

 private:
  Regions() = default;
  [[nodiscard]] SeqBlock block(const Section& s) const {
    return SeqBlock(state_ + s.offset, s.size - SeqBlock::kHeader);
  }
  bool check(std::string& error) const;
  void write_layout(const CellLayout& layout);

  Mapping state_map_, control_map_;  // empty for a view
  unsigned char* state_ = nullptr;
  unsigned char* control_ = nullptr;
  std::size_t state_size_ = 0, control_size_ = 0;
};

}  // namespace plc::hmi::ipc

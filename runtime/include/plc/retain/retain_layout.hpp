// What a cell retains, and where each value sits in a snapshot: every
// RETAIN/PERSISTENT variable of the registry and every `retain: memory:`
// range of %M, each at a fixed offset of one flat buffer. The scan thread
// copies values into the buffer (no allocation, no locks of its own), the
// writer thread serialises the buffer, and a start-up restores from a
// decoded file by path and type.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "plc/cell_config.hpp"
#include "plc/io/process_image.hpp"
#include "plc/var_registry.hpp"

namespace plc::retain {

// The type tag of a %M byte range in the file (beside the VarType codes).
inline constexpr std::uint8_t kMemoryBytes = 0xFE;

struct Entry {
  std::string path;       // `Cell.dose.TotalWeight`, or `%MB0..%MB15`
  std::uint8_t type = 0;  // VarType, or kMemoryBytes
  RetainClass cls = RetainClass::Retain;
  std::size_t offset = 0;    // in the snapshot buffer
  std::size_t size = 0;      // stored bytes (STRING: length byte + characters)
  VarInfo var;               // a variable (located ones point into the global image)
  std::size_t mem_byte = 0;  // a %M range: its first byte in the global image
  int task = -1;             // whose scans own it (-1: the global image, any task)
};

class Layout {
 public:
  // From the registry's retained variables and the config's %M ranges;
  // `global` is the image located variables and ranges are read from.
  Layout(const VarRegistry& vars, const RetainConfig& cfg, io::ProcessImage& global);
  Layout() = default;

  [[nodiscard]] const std::vector<Entry>& entries() const { return entries_; }
  [[nodiscard]] std::size_t bytes() const { return bytes_; }
  // FNV-1a over every entry's path, type and size, in order.
  [[nodiscard]] std::uint64_t hash() const { return hash_; }

  // Copies the values that `task` owns (task < 0: all) into `snapshot`
  // (bytes() long). With `image` also the %M and located %M entries. No
  // allocation; for the scan thread.
  void capture(int task, bool image, std::span<std::uint8_t> snapshot) const;
  // Writes one stored value back (start-up only).
  void restore(const Entry& e, const std::uint8_t* value) const;

  // Stored size of a value of this type (STRING: 1 + capacity).
  static std::size_t stored_size(VarType t);

 private:
  // Plain variables other than STRING, as memcpy runs: neighbours in the
  // program object that are neighbours in the snapshot too (an array, a
  // struct's fields) are one copy.
  struct Run {
    const std::uint8_t* src;
    std::size_t dst, n;
    int task;
  };
  std::vector<Entry> entries_;
  std::vector<Run> runs_;
  std::vector<std::size_t> others_;  // entries not in runs_
  std::size_t bytes_ = 0;
  std::uint64_t hash_ = 0;
  io::ProcessImage* global_ = nullptr;
};

}  // namespace plc::retain

// The published variables of one task, copied by the task's scan thread at
// the end of a scan when the bridge asks (like the debugger's real-time
// `print`): all values from the same scan, never torn. The scan thread only
// copies into memory allocated beforehand; it never encodes, allocates,
// blocks or publishes.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "plc/runtime.hpp"

namespace plc::hmi {

class ScanSnapshot {
 public:
  struct Item {
    VarInfo var;             // points into the task's memory or its image copy
    std::size_t offset = 0;  // of its value in the buffer
    int index = 0;           // in the cell description
  };
  // `items` all belong to task `task`.
  ScanSnapshot(int task, std::vector<Item> items);

  // The bridge: ask for the next scan's values.
  void request() { state_.store(kRequested, std::memory_order_release); }
  // The bridge: the values if a scan has copied them since request();
  // nullptr otherwise. Valid until the next request().
  [[nodiscard]] const unsigned char* ready() const {
    return state_.load(std::memory_order_acquire) == kFilled ? buf_.data() : nullptr;
  }
  [[nodiscard]] std::uint64_t scan() const { return scan_; }
  [[nodiscard]] TIME plc_time() const { return time_; }
  // CLOCK_REALTIME at the copy, microseconds (latency to the client).
  [[nodiscard]] std::int64_t copy_utime() const { return utime_; }

  // The scan thread, at the end of every scan of the task: one atomic load
  // when nothing is asked.
  void on_scan_end(const TaskRuntime& t, const ScanContext& ctx);

  [[nodiscard]] int task() const { return task_; }
  // How many memcpy runs and single reads one copy takes.
  [[nodiscard]] std::size_t runs() const { return runs_.size() + one_by_one_.size(); }
  [[nodiscard]] const std::vector<Item>& items() const { return items_; }

 private:
  static constexpr int kIdle = 0, kRequested = 1, kFilled = 2;
  // Program variables lying next to each other in memory (arrays, a
  // block's fields) are copied as one run; located variables and STRINGs
  // one by one through VarRegistry::read (bits, byte order).
  struct Run {
    const unsigned char* src;
    std::size_t dst, len;
  };
  int task_;
  std::vector<Item> items_;
  std::vector<Run> runs_;
  std::vector<std::size_t> one_by_one_;  // indices into items_
  std::vector<unsigned char> buf_;
  std::uint64_t scan_ = 0;
  TIME time_{};
  std::int64_t utime_ = 0;
  std::atomic<int> state_{kIdle};
};

}  // namespace plc::hmi

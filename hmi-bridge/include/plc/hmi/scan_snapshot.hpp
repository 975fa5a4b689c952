// The published variables of one task, copied by the task's scan thread at
// the end of a scan when the HMI bridge asks (like the debugger's real-time
// `print`): all values from the same scan, never torn. The copy goes into
// the task's slot in the shared memory (plc/hmi/ipc/layout.hpp: the
// request word the bridge raises, the slot's header and buffer). The scan
// thread only copies into memory mapped beforehand; it never encodes,
// allocates, blocks, publishes or makes a system call.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "plc/hmi/ipc/layout.hpp"
#include "plc/runtime.hpp"

namespace plc::hmi {

class ScanSnapshot {
 public:
  struct Item {
    VarInfo var;             // points into the task's memory or its image copy
    std::size_t offset = 0;  // of its value in the buffer (set by the constructor)
    int index = 0;           // in the cell layout
  };
  // `items` all belong to task `task`; lays out the buffer.
  ScanSnapshot(int task, std::vector<Item> items);

  // Bytes the buffer needs.
  [[nodiscard]] std::size_t buffer_size() const { return size_; }
  // Where copies go: the slot's header and buffer (buffer_size() bytes,
  // 8-aligned), and the word the bridge raises to ask (`request`). The
  // scan thread serves a request it has not served yet: it starts from the
  // slot's `filled`, so a request made before a rebuild is still served.
  void bind(ipc::SlotHeader* header, unsigned char* buffer,
            const std::atomic<std::uint64_t>* request);

  // The scan thread, at the end of every scan of the task: one atomic load
  // when nothing new is asked.
  void on_scan_end(const TaskRuntime& t, const ScanContext& ctx);

  [[nodiscard]] int task() const { return task_; }
  // How many memcpy runs and single reads one copy takes.
  [[nodiscard]] std::size_t runs() const { return runs_.size() + one_by_one_.size(); }
  [[nodiscard]] const std::vector<Item>& items() const { return items_; }

 private:
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
  std::size_t size_ = 0;
  ipc::SlotHeader* header_ = nullptr;
  unsigned char* buf_ = nullptr;
  const std::atomic<std::uint64_t>* request_ = nullptr;
  std::uint64_t served_ = 0;  // the last request copied (only the scan thread touches it)
};

}  // namespace plc::hmi

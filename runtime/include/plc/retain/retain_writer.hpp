// Saves retain snapshots on its own (normal, non-real-time) thread, so that
// a scan never waits on the disk. The scan side offers a snapshot (one
// memcpy into a preallocated buffer, no allocation, no lock); when the
// writer is still busy with the previous one, the offer is skipped and
// counted instead. The writer encodes the snapshot and writes it through
// Storage only when it differs from the last one written. A failed write (a
// full disk) is reported on stderr, counted, and retried with the next
// snapshot; the scans go on.
//
// Layouts: each snapshot is offered through the Slot of its own layout,
// and the writer encodes it with that layout, so a file is always one
// layout's header, entries and values. An online change (Manager) moves
// the scans to a new layout's slot; a snapshot offered before the switch
// and written after it is still written whole in its old layout.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "plc/retain/retain_layout.hpp"
#include "plc/retain/retain_storage.hpp"

namespace plc::retain {

struct WriterStats {
  std::uint64_t offered = 0;    // snapshots handed to the writer
  std::uint64_t skipped = 0;    // due, but the writer was busy
  std::uint64_t written = 0;    // files written
  std::uint64_t unchanged = 0;  // snapshots equal to the last file: not written
  std::uint64_t failed = 0;     // writes that failed
  std::uint64_t sequence = 0;   // of the last file written
  std::string last_error;       // of the last failed write ("" after a success)
};

class Writer {
 public:
  // One layout's hand-over buffer: made (allocated) outside the scans, and
  // kept as long as the writer may still hold a snapshot in it (holds()).
  struct Slot {
    explicit Slot(const Layout& l) : layout(&l), bytes(l.bytes()) {}
    const Layout* layout;
    std::vector<std::uint8_t> bytes;
  };

  explicit Writer(Storage& storage);
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // Tests: runs on the writer thread before each write (a stalled disk).
  // Set before start().
  void set_before_write(std::function<void()> f) { before_write_ = std::move(f); }
  // Starts the thread; `next_sequence` numbers the first file it writes.
  void start(std::uint64_t next_sequence);

  // Scan thread: hands `snapshot` (slot.layout->bytes() long) to the
  // writer through `slot`, or counts a skip when it is busy. Never waits,
  // never allocates.
  bool offer(Slot& slot, std::span<const std::uint8_t> snapshot);
  // After the last scan: lets the thread finish, then writes `final_snapshot`
  // of `layout` on the calling thread (when it changed). "" or the error.
  std::string stop(const Layout& layout, std::span<const std::uint8_t> final_snapshot);
  // Whether a snapshot offered through `slot` waits or is being written:
  // while true the slot (and its layout) must live. Once false it stays
  // false until the slot is offered again.
  [[nodiscard]] bool holds(const Slot& slot) const {
    return busy() && pending_.load(std::memory_order_relaxed) == &slot;
  }

  [[nodiscard]] WriterStats stats() const;
  // How long a file write takes lately (the longest of the recent ones,
  // decaying by 1/8 per write): the scan side takes its snapshots that much
  // early, so that the newest complete copy stays within a save period.
  [[nodiscard]] std::chrono::nanoseconds write_lead() const {
    return std::chrono::nanoseconds(write_lead_ns_.load(std::memory_order_relaxed));
  }
  [[nodiscard]] bool busy() const { return (state_.load(std::memory_order_acquire) & kFull) != 0; }

 private:
  static constexpr std::uint32_t kFull = 1, kStop = 2;
  void run();
  std::string write_one(const Layout& layout, std::span<const std::uint8_t> snapshot);

  Storage& storage_;
  // The slot filled by the last offer(): set before kFull is (release),
  // read by the thread after it saw kFull (acquire).
  std::atomic<Slot*> pending_{nullptr};
  std::vector<std::uint8_t> last_;     // writer only: the last content written
  std::uint64_t last_hash_ = 0;        // ... and its layout's hash
  std::vector<std::uint8_t> encoded_;  // writer only: reused file image
  bool have_last_ = false;
  std::atomic<std::uint32_t> state_{0};
  std::atomic<std::uint64_t> offered_{0}, skipped_{0};
  std::atomic<std::int64_t> write_lead_ns_{0};
  std::atomic<bool> dead_{false};  // the thread failed (plc/thread_guard.hpp)
  mutable std::mutex mu_;          // the fields below (writer side, read by stats())
  std::uint64_t written_ = 0, unchanged_ = 0, failed_ = 0, sequence_ = 0, next_sequence_ = 1;
  std::string last_error_;
  std::function<void()> before_write_;
  std::thread thread_;
};

}  // namespace plc::retain

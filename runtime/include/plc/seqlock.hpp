// A sequence lock for data that one thread writes and other threads read:
// the writer never blocks, never allocates and never waits for a reader; a
// reader copies the data and retries when a write overlapped its copy, so
// what it gets is one consistent state (all fields from the same writes).
//
// The data it guards must be SeqLockCell<T> (or other atomics with the same
// orders): a reader's copy races with the writer by design, and only atomic
// accesses make that defined. A cell's store is a release and its load an
// acquire; on x86-64 both are plain moves, so the writer pays no fence and no
// locked instruction, and the orders keep every data store after the opening
// sequence store and every data load before the closing sequence load
// (Boehm, "Can seqlocks get along with programming language memory models?",
// MSPC 2012) without standalone fences, which ThreadSanitizer cannot model.
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>

namespace plc {

// A value written by one thread and read by any (see above). Copying takes a
// snapshot of the value.
template <class T>
class SeqLockCell {
 public:
  SeqLockCell(T v = T{}) : v_(v) {}  // NOLINT(google-explicit-constructor): a drop-in value
  SeqLockCell(const SeqLockCell& o) : v_(T(o)) {}
  SeqLockCell& operator=(const SeqLockCell& o) { return *this = T(o); }
  operator T() const { return v_.load(std::memory_order_acquire); }  // NOLINT
  SeqLockCell& operator=(T v) {
    v_.store(v, std::memory_order_release);
    return *this;
  }
  // Writer only (a load and a store, not a locked read-modify-write).
  SeqLockCell& operator++() { return *this += T(1); }
  SeqLockCell& operator+=(T d) {
    v_.store(T(v_.load(std::memory_order_relaxed) + d), std::memory_order_release);
    return *this;
  }

 private:
  std::atomic<T> v_;
};

class SeqLock {
 public:
  // Writer: brackets one update of the guarded cells.
  void write_begin() {
    seq_.store(seq_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  }
  void write_end() {
    seq_.store(seq_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  }

  // Reader: runs `copy` (which loads the guarded cells) until it ran with no
  // write in between; false if every one of `tries` attempts overlapped a
  // write (the last copy is then not consistent). A writer holds the lock
  // for the few stores of one update, so the first try nearly always wins.
  template <class F>
  bool read(F&& copy, int tries = 10000) const {
    for (int i = 1;; ++i) {
      const std::uint64_t before = seq_.load(std::memory_order_acquire);
      const bool writing = (before & 1) != 0;
      if (writing && i < tries) {
        std::this_thread::yield();
        continue;
      }
      copy();
      if (!writing && seq_.load(std::memory_order_relaxed) == before) return true;
      if (i >= tries) return false;
    }
  }

 private:
  std::atomic<std::uint64_t> seq_{0};  // odd while a write is under way
};

}  // namespace plc

// The plugin-side state of one configured device that FBs can reach: its
// communication state and its queue of acyclic requests.
//
// Submitting never blocks and never allocates: the queue is a fixed ring
// guarded by a spinlock held for a few instructions (several tasks may use
// one device). The plugin drains it from its own context.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "plc/io/record_request.hpp"

namespace plc::io {

enum class DeviceState : std::uint8_t {
  Offline,  // not started, or stopped answering
  Online,   // cyclic data is valid
  Fault,    // the plugin reports a communication or configuration fault
};
const char* to_string(DeviceState s);

class DeviceLink {
 public:
  static constexpr std::size_t kQueueDepth = 16;

  [[nodiscard]] DeviceState state() const { return state_.load(std::memory_order_acquire); }
  void set_state(DeviceState s) { state_.store(s, std::memory_order_release); }

  // FB side: queue a prepared request. Returns false (and marks the request
  // failed with QueueFull or NotReachable) if it cannot be taken.
  bool submit(RecordRequest& r);

  // Plugin side: take the oldest queued request, or nullptr.
  RecordRequest* pop();
  [[nodiscard]] std::size_t pending() const;

  // Recording: remember submitted requests until their answer has been
  // collected, so a recorder can log each answer in the scan that first
  // sees it. Off unless a recorder turns it on.
  void set_tracking(bool on);
  // Calls f(request) for each tracked request that has been answered, and
  // forgets it. In submission order.
  template <class F>
  void collect_answered(F&& f) {
    lock();
    std::size_t keep = 0;
    for (std::size_t i = 0; i < tracked_n_; ++i) {
      RecordRequest* r = tracked_[i];
      if (r->status() == RecordStatus::Done || r->status() == RecordStatus::Error)
        f(*r);
      else
        tracked_[keep++] = r;
    }
    tracked_n_ = keep;
    unlock();
  }

 private:
  void lock() const {
    while (lock_.test_and_set(std::memory_order_acquire)) {
    }
  }
  void unlock() const { lock_.clear(std::memory_order_release); }

  std::array<RecordRequest*, kQueueDepth> ring_{};
  std::size_t head_ = 0, count_ = 0;
  std::uint32_t next_seq_ = 0;
  bool tracking_ = false;
  std::array<RecordRequest*, 2 * kQueueDepth> tracked_{};
  std::size_t tracked_n_ = 0;
  mutable std::atomic_flag lock_ = ATOMIC_FLAG_INIT;
  std::atomic<DeviceState> state_{DeviceState::Offline};
};

}  // namespace plc::io

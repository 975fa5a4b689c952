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
#include "plc/types.hpp"

namespace plc::io {

// The last alarm a device reported (PROFINET alarm notification: type,
// where, and the user structure identifier with the first 4 data bytes, e.g.
// a channel diagnosis' error type). Plugins without alarms leave it empty.
struct DeviceAlarm {
  std::uint32_t count = 0;  // alarms reported since start; 0 = none yet
  std::uint16_t type = 0;   // AlarmType (1 = diagnosis, 2 = process, ...)
  std::uint16_t slot = 0, subslot = 0;
  std::uint16_t usi = 0;   // user structure identifier (0x8000 = channel diagnosis)
  std::uint32_t data = 0;  // first 4 bytes of the alarm item after the USI, big-endian
  bool appears = true;     // false: the diagnosis disappeared (alarm specifier)
};

enum class DeviceState : std::uint8_t {
  Offline,  // not started, or stopped answering
  Online,   // cyclic data is valid
  Fault,    // the plugin reports a communication or configuration fault
};
const char* to_string(DeviceState s);

class DeviceLink {
 public:
  static constexpr std::size_t kQueueDepth = 16;

  // The state FBs see. Deferred: the state as of the owning task's last
  // latch; otherwise the plugin's present state.
  [[nodiscard]] DeviceState state() const {
    return (deferred_ ? latched_state_ : state_).load(std::memory_order_acquire);
  }
  // Plugin side: the present state, and setting it.
  [[nodiscard]] DeviceState live_state() const { return state_.load(std::memory_order_acquire); }
  // A change is counted in the runtime's total (set_deferred()): a latch
  // that finds the total as its task's last latch left it skips the links
  // (no state can differ from its latched one). The exchange keeps every
  // store (the last writer wins, as before); counted after it, so a latch
  // that reads the old total sees no store it would have missed.
  void set_state(DeviceState s) {
    const DeviceState before = state_.exchange(s, std::memory_order_acq_rel);
    if (before != s && state_changes_) state_changes_->fetch_add(1, std::memory_order_release);
  }
  // Replay: set the present and the latched state at once (equal: not
  // counted as a change, no latch needs to copy it).
  void force_state(DeviceState s) {
    state_.store(s, std::memory_order_release);
    latched_state_.store(s, std::memory_order_release);
  }

  // Scan-consistent delivery, turned on by the Runtime for every device:
  // answers to acyclic requests and the communication state change only at
  // a scan's latch, never in the middle of a scan (see record_request.hpp).
  // A request remembers the task that submitted it (the scan thread's
  // current owner) and is delivered at that task's next latch.
  // `tracking_total` (optional): a count, shared by the links of one
  // runtime, of the links whose tracking() is true, so that a latch can
  // skip looking at every link when none tracks anything (the usual scan).
  // `state_changes` (optional): a count, shared likewise, of the changes
  // set_state() made (set_state()).
  void set_deferred(bool on, std::atomic<std::uint32_t>* tracking_total = nullptr,
                    std::atomic<std::uint64_t>* state_changes = nullptr);
  static void set_current_owner(int owner);
  // At a latch of the owning task: copy the plugin's state for FBs. A
  // change is noted with that scan's number (1 = the task's first) and PLC
  // time, for readers on other threads (the HMI bridge's device alarms):
  // however briefly a state lasts, a scan that saw it is counted. The scan
  // thread pays a compare when nothing changed.
  void latch_state(std::uint64_t scan = 0, TIME now = TIME(0)) {
    const DeviceState s = live_state();
    const DeviceState before = latched_state_.load(std::memory_order_relaxed);
    if (s == before) return;
    latched_state_.store(s, std::memory_order_release);
    note_change(before, s, scan, now);
  }
  // The last change latch_state() noted, and how many it noted in all
  // (count 0: none). Lock-free, from any thread.
  struct StateChange {
    std::uint64_t count = 0;
    DeviceState from = DeviceState::Offline, to = DeviceState::Offline;
    std::uint64_t scan = 0;
    TIME time{0};
    bool torn = false;  // the writer was mid-update at every try: only count is known
  };
  [[nodiscard]] StateChange last_change() const;
  // Whether any request is tracked (deferred links): a latch with nothing
  // to deliver skips deliver_answered() and its lock. A request submitted
  // on another thread at this moment cannot have an answer parked yet.
  [[nodiscard]] bool tracking() const { return tracking_.load(std::memory_order_acquire); }
  // At a latch of task `owner`: make the parked answers of its requests
  // visible, calling f(request) for each (recording), in submission order.
  // Requests finished without parking (refusals, replay) are forgotten.
  template <class F>
  void deliver_answered(int owner, F&& f) {
    lock();
    std::size_t keep = 0;
    for (std::size_t i = 0; i < tracked_n_; ++i) {
      RecordRequest* r = tracked_[i];
      const RecordStatus st = r->status();
      if (st == RecordStatus::Done || st == RecordStatus::Error) continue;
      if (r->answer_parked() && (r->owner() == owner || r->owner() < 0 || owner < 0) &&
          r->deliver()) {
        f(*r);
        continue;
      }
      tracked_[keep++] = r;
    }
    tracked_n_ = keep;
    set_tracking(keep != 0);
    unlock();
  }

  // FB side: queue a prepared request. Returns false (and marks the request
  // failed with QueueFull or NotReachable) if it cannot be taken.
  bool submit(RecordRequest& r);

  // Plugin side: take the oldest queued request, or nullptr.
  RecordRequest* pop();
  // Whether pop() may find a request, without the lock: a device steps
  // every millisecond and is asked something now and then. A submit that
  // races with this read is found at the device's next step.
  [[nodiscard]] bool maybe_queued() const { return queued_.load(std::memory_order_acquire); }
  // Replay: `r` was answered directly (not parked); stop tracking it. An
  // answer the program saw and reset before the next latch would otherwise
  // stay tracked, and resubmitting the same request fills the table.
  void untrack(const RecordRequest* r);
  [[nodiscard]] std::size_t pending() const;
  // Submitted requests whose answer no program has seen yet (queued, in
  // the plugin's hands, or parked until their task's next latch).
  [[nodiscard]] std::size_t in_flight() const;
  // The number the last submitted request got. A recording started
  // mid-session keeps it in its snapshot and the replay sets it back, so
  // the replayed requests are numbered as the recorded ones.
  [[nodiscard]] std::uint32_t last_seq() const;
  void set_last_seq(std::uint32_t seq);

  // The device's last alarm (live, not latched: an alarm is an event, FBs
  // compare count with the one they saw). Plugin side: post_alarm().
  [[nodiscard]] DeviceAlarm last_alarm() const {
    lock();
    const DeviceAlarm a = alarm_;
    unlock();
    return a;
  }
  void post_alarm(DeviceAlarm a) {
    lock();
    a.count = alarm_.count + 1;
    alarm_ = a;
    unlock();
  }

 private:
  void lock() const {
    while (lock_.test_and_set(std::memory_order_acquire)) {
    }
  }
  void unlock() const { lock_.clear(std::memory_order_release); }
  // Under the lock: tracking_ and the runtime's total with it.
  void set_tracking(bool on) {
    if (on == tracking_.load(std::memory_order_relaxed)) return;
    tracking_.store(on, std::memory_order_release);
    if (tracking_total_) {
      if (on)
        tracking_total_->fetch_add(1, std::memory_order_release);
      else
        tracking_total_->fetch_sub(1, std::memory_order_release);
    }
  }

  std::array<RecordRequest*, kQueueDepth> ring_{};
  std::size_t head_ = 0, count_ = 0;
  std::uint32_t next_seq_ = 0;
  bool deferred_ = false;
  // Deferred links: submitted requests whose answer has not been delivered
  // yet (queued or in the plugin's hands). A submission that would not fit
  // is refused with QueueFull rather than lose track of one.
  std::array<RecordRequest*, 4 * kQueueDepth> tracked_{};
  std::size_t tracked_n_ = 0;
  std::atomic<bool> tracking_{false};  // tracked_n_ != 0, readable without the lock
  std::atomic<std::uint32_t>* tracking_total_ = nullptr;  // set_deferred()
  std::atomic<std::uint64_t>* state_changes_ = nullptr;   // set_deferred()
  std::atomic<bool> queued_{false};                       // count_ != 0, readable without the lock
  mutable std::atomic_flag lock_ = ATOMIC_FLAG_INIT;
  std::atomic<DeviceState> state_{DeviceState::Offline};
  std::atomic<DeviceState> latched_state_{DeviceState::Offline};
  // The last noted change, under a sequence count (odd while the one
  // writer, the owning task's scan thread, updates it; changes = seq / 2).
  void note_change(DeviceState from, DeviceState to, std::uint64_t scan, TIME now);
  std::atomic<std::uint64_t> change_seq_{0};
  std::atomic<std::uint8_t> change_from_{0}, change_to_{0};
  std::atomic<std::uint64_t> change_scan_{0};
  std::atomic<std::int64_t> change_time_ns_{0};
  DeviceAlarm alarm_{};  // under lock_
};

}  // namespace plc::io

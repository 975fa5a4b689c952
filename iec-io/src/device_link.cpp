#include "plc/io/device_link.hpp"

#include "plc/io/current_owner.hpp"

namespace plc::io {

const char* to_string(DeviceState s) {
  switch (s) {
    case DeviceState::Offline:
      return "offline";
    case DeviceState::Online:
      return "online";
    case DeviceState::Fault:
      return "fault";
  }
  return "?";
}

// Initial-exec and constinit: current_owner.hpp (the runtime's scan sets it
// inline).
constinit thread_local int detail::tl_current_owner __attribute__((tls_model("initial-exec"))) = -1;

void DeviceLink::set_current_owner(int owner) { detail::set_current_owner(owner); }

bool DeviceLink::submit(RecordRequest& r) {
  if (state() != DeviceState::Online) {
    r.set_delivery(false, -1);  // a refusal is an answer given at once
    r.fail(RecordError::NotReachable);
    return false;
  }
  lock();
  if (count_ == kQueueDepth || (deferred_ && tracked_n_ == tracked_.size())) {
    unlock();
    r.set_delivery(false, -1);
    r.fail(RecordError::QueueFull);
    return false;
  }
  r.set_seq(++next_seq_);
  r.set_delivery(deferred_, detail::tl_current_owner);
  r.mark_queued();
  ring_[(head_ + count_) % kQueueDepth] = &r;
  ++count_;
  queued_.store(true, std::memory_order_release);
  if (deferred_) {
    tracked_[tracked_n_++] = &r;  // room checked above
    set_tracking(true);
  }
  unlock();
  return true;
}

RecordRequest* DeviceLink::pop() {
  lock();
  RecordRequest* r = nullptr;
  if (count_ > 0) {
    r = ring_[head_];
    head_ = (head_ + 1) % kQueueDepth;
    --count_;
    queued_.store(count_ != 0, std::memory_order_release);
  }
  unlock();
  return r;
}

void DeviceLink::untrack(const RecordRequest* r) {
  lock();
  std::size_t keep = 0;
  for (std::size_t i = 0; i < tracked_n_; ++i)
    if (tracked_[i] != r) tracked_[keep++] = tracked_[i];
  tracked_n_ = keep;
  set_tracking(keep != 0);
  unlock();
}

// A sequence count around the fields (no fences: ThreadSanitizer does not
// model them). The odd count is stored before the fields, and each field's
// release store keeps it ordered before; a reader that saw a field of this
// change then sees the count changed on its second load.
void DeviceLink::note_change(DeviceState from, DeviceState to, std::uint64_t scan, TIME now) {
  const std::uint64_t seq = change_seq_.load(std::memory_order_relaxed);
  change_seq_.store(seq + 1, std::memory_order_relaxed);
  change_from_.store(static_cast<std::uint8_t>(from), std::memory_order_release);
  change_to_.store(static_cast<std::uint8_t>(to), std::memory_order_release);
  change_scan_.store(scan, std::memory_order_release);
  change_time_ns_.store(now.count(), std::memory_order_release);
  change_seq_.store(seq + 2, std::memory_order_release);
}

DeviceLink::StateChange DeviceLink::last_change() const {
  StateChange c;
  // Bounded: a change is rare, so a reader overlapping one retries at most
  // a few times; after 1000 (the writer preempted mid-update) it says so.
  for (int i = 0; i < 1000; ++i) {
    const std::uint64_t s1 = change_seq_.load(std::memory_order_acquire);
    if (s1 % 2) continue;
    c.count = s1 / 2;
    c.from = static_cast<DeviceState>(change_from_.load(std::memory_order_acquire));
    c.to = static_cast<DeviceState>(change_to_.load(std::memory_order_acquire));
    c.scan = change_scan_.load(std::memory_order_acquire);
    c.time = TIME(change_time_ns_.load(std::memory_order_acquire));
    if (change_seq_.load(std::memory_order_relaxed) == s1) return c;
  }
  c = StateChange{};
  c.count = change_seq_.load(std::memory_order_acquire) / 2;
  c.torn = true;
  return c;
}

void DeviceLink::set_deferred(bool on, std::atomic<std::uint32_t>* tracking_total,
                              std::atomic<std::uint64_t>* state_changes) {
  lock();
  state_changes_ = state_changes;
  // The total counts this link from now on (as tracking or not).
  if (tracking_total_ && tracking_.load(std::memory_order_relaxed))
    tracking_total_->fetch_sub(1, std::memory_order_release);
  tracking_total_ = tracking_total;
  if (tracking_total_ && tracking_.load(std::memory_order_relaxed))
    tracking_total_->fetch_add(1, std::memory_order_release);
  deferred_ = on;
  latched_state_.store(live_state(), std::memory_order_release);
  unlock();
}

std::size_t DeviceLink::pending() const {
  lock();
  const std::size_t n = count_;
  unlock();
  return n;
}

std::uint32_t DeviceLink::last_seq() const {
  lock();
  const std::uint32_t n = next_seq_;
  unlock();
  return n;
}

void DeviceLink::set_last_seq(std::uint32_t seq) {
  lock();
  next_seq_ = seq;
  unlock();
}

std::size_t DeviceLink::in_flight() const {
  lock();
  const std::size_t n = deferred_ ? tracked_n_ : count_;
  unlock();
  return n;
}

}  // namespace plc::io

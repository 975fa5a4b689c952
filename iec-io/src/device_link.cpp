#include "plc/io/device_link.hpp"

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

namespace {
thread_local int tl_owner = -1;
}

void DeviceLink::set_current_owner(int owner) { tl_owner = owner; }

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
  r.set_delivery(deferred_, tl_owner);
  r.mark_queued();
  ring_[(head_ + count_) % kQueueDepth] = &r;
  ++count_;
  if (deferred_) tracked_[tracked_n_++] = &r;  // room checked above
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
  unlock();
}

void DeviceLink::set_deferred(bool on) {
  lock();
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

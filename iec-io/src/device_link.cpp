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

bool DeviceLink::submit(RecordRequest& r) {
  if (state() != DeviceState::Online) {
    r.fail(RecordError::NotReachable);
    return false;
  }
  lock();
  if (count_ == kQueueDepth) {
    unlock();
    r.fail(RecordError::QueueFull);
    return false;
  }
  r.set_seq(++next_seq_);
  r.mark_queued();
  ring_[(head_ + count_) % kQueueDepth] = &r;
  ++count_;
  if (tracking_ && tracked_n_ < tracked_.size()) tracked_[tracked_n_++] = &r;
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

void DeviceLink::set_tracking(bool on) {
  lock();
  tracking_ = on;
  if (!on) tracked_n_ = 0;
  unlock();
}

std::size_t DeviceLink::pending() const {
  lock();
  const std::size_t n = count_;
  unlock();
  return n;
}

}  // namespace plc::io

#include "plc/hmi/memq_transport.hpp"

#include <chrono>

#include "plc/hmi/udpm_wire.hpp"
#include "plc/hmi/utime.hpp"

namespace plc::hmi {

bool MemqTransport::publish(const std::string& channel, const void* data, std::size_t size) {
  std::unique_lock<std::mutex> lock(mu_);
  if (channel.size() > udpm::kMaxChannelLength || size > max_message_) {
    ++counters_.too_large_to_send;
    return false;
  }
  lock.unlock();
  if (!subscribed(channel)) return true;  // sent, to nobody
  Queued q;
  q.channel = channel;
  q.data.assign(static_cast<const std::uint8_t*>(data),
                static_cast<const std::uint8_t*>(data) + size);
  q.utime = utime_now();
  lock.lock();
  if (queue_.size() >= kMaxQueued) {
    ++counters_.queue_full;
    return false;
  }
  queue_.push_back(std::move(q));
  lock.unlock();
  cv_.notify_one();
  return true;
}

int MemqTransport::handle_timeout(int timeout_ms) {
  std::unique_lock<std::mutex> lock(mu_);
  if (!cv_.wait_for(lock, std::chrono::milliseconds(std::max(timeout_ms, 0)),
                    [this] { return !queue_.empty(); }))
    return 0;
  Queued q = std::move(queue_.front());
  queue_.pop_front();
  ++counters_.messages;
  lock.unlock();
  const ReceiveBuffer rb{q.data.data(), q.data.size(), q.utime};
  TransportCounters thrown;
  dispatch(q.channel, rb, thrown);
  lock.lock();
  counters_.handler_exceptions += thrown.handler_exceptions;
  return 1;
}

TransportCounters MemqTransport::counters() const {
  std::lock_guard<std::mutex> lock(mu_);
  return counters_;
}

}  // namespace plc::hmi

// memq://: messages published into a queue of this transport and handed to
// its own subscriptions by handle_timeout, in order (liblcm's lcm_memq.c
// semantics: a message nobody subscribes to is dropped when published).
// Our own rather than liblcm's, so the tests run the same subscription,
// dispatch and counting code as udpm://, and nothing in the bridge or plcctl
// needs liblcm's lcm::LCM any more. No network, nothing parsed.
#pragma once

#include <condition_variable>
#include <deque>
#include <mutex>

#include "plc/hmi/transport.hpp"

namespace plc::hmi {

class MemqTransport final : public Transport {
 public:
  // At most this many messages wait; more are dropped and counted.
  static constexpr std::size_t kMaxQueued = 10000;

  explicit MemqTransport(const UdpmLimits& limits = {}) : max_message_(limits.max_message_bytes) {}
  using Transport::publish;
  bool publish(const std::string& channel, const void* data, std::size_t size) override;
  int handle_timeout(int timeout_ms) override;
  [[nodiscard]] TransportCounters counters() const override;

 private:
  struct Queued {
    std::string channel;
    std::vector<std::uint8_t> data;
    std::int64_t utime = 0;
  };
  std::size_t max_message_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<Queued> queue_;
  TransportCounters counters_;
};

}  // namespace plc::hmi

// How the bridge and plcctl send and receive LCM messages: our own
// transport in place of liblcm's lcm::LCM (issue 22), with two
// implementations behind one small interface:
//   udpm://  UDP multicast, byte-compatible with liblcm 1.3.1
//            (udpm_transport.hpp; bounded receiver: udpm_receiver.hpp)
//   memq://  in-process queue, for tests and benchmarks (memq_transport.hpp)
// Messages are encoded and decoded with lcm-gen's classes as before
// (publish<T> below; checked_decode.hpp on the way in).
//
// Threads, as liblcm's rule: subscribe, unsubscribe and handle_timeout from
// one thread; publish from any (memq:// wakes a waiting handle_timeout).
// Handlers run inside handle_timeout, on that thread.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <regex>
#include <string>
#include <string_view>
#include <vector>

#include "plc/hmi/transport_counters.hpp"
#include "plc/hmi/udpm_receiver.hpp"

namespace plc::hmi {

// One received message, valid during the handler's call (the fields of
// lcm::ReceiveBuffer that we use).
struct ReceiveBuffer {
  const void* data = nullptr;
  std::size_t data_size = 0;
  std::int64_t recv_utime = 0;  // arrival, microseconds since the epoch
};

class Transport {
 public:
  using Handler = std::function<void(const ReceiveBuffer& rb, const std::string& channel)>;
  struct Subscription;

  virtual ~Transport();

  // `channel` is matched against the whole channel name as a regular
  // expression (liblcm: "^channel$"): an exact name, or e.g. "PLC_.*".
  // Throws std::regex_error for a pattern that does not compile.
  Subscription* subscribe(const std::string& channel, Handler handler);
  // Also from inside a handler; the handler runs no more afterwards.
  void unsubscribe(Subscription* s);

  // Sends one message. False when it cannot be sent (channel over 63
  // characters, larger than the maximum message size, a socket error):
  // counted, never thrown.
  virtual bool publish(const std::string& channel, const void* data, std::size_t size) = 0;
  // An lcm-gen message, encoded.
  template <class T>
  bool publish(const std::string& channel, const T* msg) {
    const int n = msg->getEncodedSize();
    if (n < 0) return false;
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(n));
    if (msg->encode(buf.data(), 0, n) != n) return false;
    return publish(channel, buf.data(), buf.size());
  }

  // Waits up to timeout_ms for one message and hands it to its handlers.
  // Returns 1 when one was handled, 0 when none came in time, -1 when the
  // transport failed (a socket error). Handlers that throw are counted.
  virtual int handle_timeout(int timeout_ms) = 0;

  [[nodiscard]] virtual TransportCounters counters() const = 0;

 protected:
  // Whether a subscription matches (any thread).
  bool subscribed(std::string_view channel) const;
  // Hands a message to every matching subscription; returns how many.
  // Never throws (handler_exceptions counts what handlers throw).
  int dispatch(std::string_view channel, const ReceiveBuffer& rb, TransportCounters& counters);

 private:
  mutable std::mutex subs_mu_;
  std::vector<std::shared_ptr<Subscription>> subs_;
};

struct Transport::Subscription {
  std::string pattern;
  std::optional<std::regex> re;  // none: an exact name
  Handler handler;
  std::atomic<bool> active{true};
  [[nodiscard]] bool matches(std::string_view channel) const;
};

// Opens the transport of `url` (lcm_url.hpp). nullptr and `error` (what is
// wrong, and what to do about a missing multicast route) when it cannot.
std::unique_ptr<Transport> open_transport(const std::string& url, std::string& error,
                                          const UdpmLimits& limits = {});

}  // namespace plc::hmi

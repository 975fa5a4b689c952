// plcctl's side of the bridge: sends commands (signed when a key is given)
// and waits, within a deadline, for the reply that carries their request id
// or for the next message of a channel.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "plc/hmi/channels.hpp"
#include "plc/hmi/checked_decode.hpp"
#include "plc/hmi/command_auth.hpp"
#include "plc/hmi/transport.hpp"
#include "softplc_hmi/cell_description_t.hpp"
#include "softplc_hmi/reply_t.hpp"

namespace plc::hmi {

class Client {
 public:
  // Throws std::runtime_error when `url` is wrong or cannot be opened.
  Client(const std::string& url, const std::string& prefix, std::optional<Key> key,
         std::chrono::milliseconds timeout);
  // The reply, or nullopt (and `err`) when none came in time.
  std::optional<softplc_hmi::reply_t> command(const std::string& verb,
                                              const std::vector<std::string>& args,
                                              std::string& err);
  // The cell description (asks for it with a `describe` command).
  std::optional<softplc_hmi::cell_description_t> describe(std::string& err);
  // The next message on `channel`, decoded as T, within the timeout.
  template <class T>
  std::optional<T> next(const std::string& channel) {
    std::optional<T> got;
    Catch<T> c{&got};
    auto* s = subscribe_checked<T>(*transport_, channel, &c);
    wait([&] { return got.has_value(); });
    transport_->unsubscribe(s);
    return got;
  }
  Transport& transport() { return *transport_; }
  const Channels& channels() const { return ch_; }

  // Handles messages until done() or the timeout.
  template <class F>
  bool wait(F done) {
    const auto deadline = std::chrono::steady_clock::now() + timeout_;
    while (!done()) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return false;
      transport_->handle_timeout(int(std::min<std::int64_t>(left.count(), 100)));
    }
    return true;
  }

 private:
  template <class T>
  struct Catch {
    std::optional<T>* out;
    void on(const T& m) {
      if (!*out) *out = m;
    }
  };
  std::unique_ptr<Transport> transport_;
  Channels ch_;
  std::optional<Key> key_;
  std::chrono::milliseconds timeout_;
  std::string client_;
  std::int64_t next_id_ = 1;
};

}  // namespace plc::hmi

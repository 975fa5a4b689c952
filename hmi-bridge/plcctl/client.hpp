// plcctl's side of the bridge: sends commands and waits, within a deadline,
// for the reply that carries their request id or for the next message of a
// channel.
//
// With a key (hmi-bridge/README.md, "Authentication") it first learns the
// cell's name and boot epoch from a cell description whose tag verifies,
// signs every command for them, and takes as the answer only a reply to
// that command's random request id whose tag verifies: unsigned, forged
// and other clients' replies are passed over, and it keeps waiting for the
// real one until its timeout.
#pragma once

#include <chrono>
#include <functional>
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
  // The reply, or nullopt (and `err`) when none came in time. With a key:
  // a "stale epoch" refusal (the bridge started again since the epoch was
  // learnt) is answered by sending the command once more for the epoch the
  // signed refusal gives.
  std::optional<softplc_hmi::reply_t> command(const std::string& verb,
                                              const std::vector<std::string>& args,
                                              std::string& err);
  // The cell description (asks for it with a `describe` command); with a
  // key only one whose tag verifies, and the client then signs for its
  // cell and epoch.
  std::optional<softplc_hmi::cell_description_t> describe(std::string& err);
  // Called with every command right after it is published (tests answer
  // it on this client's transport).
  std::function<void(const softplc_hmi::command_t&)> on_sent;
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
  std::optional<softplc_hmi::reply_t> command_once(const std::string& verb,
                                                   const std::vector<std::string>& args,
                                                   std::string& err);
  std::int64_t next_counter();
  std::unique_ptr<Transport> transport_;
  Channels ch_;
  std::string prefix_;
  std::optional<Key> key_;
  std::chrono::milliseconds timeout_;
  std::string client_;
  std::int64_t last_counter_ = 0;
  // With a key: what the last verified description said.
  std::optional<std::string> cell_;
  Epoch epoch_{};
};

}  // namespace plc::hmi

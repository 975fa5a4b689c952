// The shared core of MemoryEthernet and MemoryUdp: a segment of endpoints
// keyed by address, queues of whole messages, and the fault hooks (drop or
// delay the next n messages from a sender, link down). Private to src/link.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <vector>

#include "plc/profinet/link/ethernet_port.hpp"
#include "plc/profinet/link/memory_ethernet.hpp"

namespace plc::profinet::detail {

template <class Sender, class Extra, class Less = std::less<Sender>>
class MemorySegment {
 public:
  struct Message {
    std::vector<std::uint8_t> bytes;
    Extra extra{};  // the UDP source; nothing for Ethernet
    std::chrono::nanoseconds due{0};
  };
  struct Endpoint {
    Sender address{};
    std::deque<Message> queue;
    LinkCounters* counters = nullptr;
  };
  struct Faults {
    int drop = 0;
    int delay = 0;
    std::chrono::nanoseconds delay_by{0};
    bool down = false;
  };

  std::mutex mutex;
  std::condition_variable arrived;
  std::map<std::uint64_t, Endpoint> endpoints;            // by endpoint key
  std::map<Sender, Faults, Less> faults;                  // by sender address
  std::deque<std::pair<std::uint64_t, Message>> delayed;  // (receiver key, message)
  std::chrono::nanoseconds now{0};
  std::uint64_t carried = 0;

  // The helpers below expect the mutex held.
  bool link_down(const Sender& s) {
    auto it = faults.find(s);
    return it != faults.end() && it->second.down;
  }
  // Returns: 0 deliver, 1 dropped, 2 delayed (with `due` set).
  int take_fault(const Sender& s, std::chrono::nanoseconds& due) {
    auto it = faults.find(s);
    if (it == faults.end()) return 0;
    if (it->second.drop > 0) {
      --it->second.drop;
      return 1;
    }
    if (it->second.delay > 0) {
      --it->second.delay;
      due = now + it->second.delay_by;
      return 2;
    }
    return 0;
  }
  void enqueue(std::uint64_t key, Message m) {
    auto it = endpoints.find(key);
    if (it == endpoints.end() || link_down(it->second.address)) return;  // lost
    if (it->second.queue.size() >= kMemoryQueueLimit) {
      it->second.counters->rx_dropped.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    it->second.queue.push_back(std::move(m));
  }
  // Sends `m` from `from` to each receiver key that `to` accepts; false if
  // the sender's link is down.
  template <class Accept>
  bool send(const Sender& from, std::uint64_t self, Message m, Accept to) {
    {
      std::lock_guard lock(mutex);
      if (link_down(from)) return false;
      ++carried;
      std::chrono::nanoseconds due{0};
      const int fault = take_fault(from, due);
      if (fault == 1) return true;  // lost on the way, as a real link loses frames
      std::vector<std::uint64_t> keys;
      for (auto& [k, ep] : endpoints)
        if (k != self && to(k, ep)) keys.push_back(k);
      for (std::size_t i = 0; i < keys.size(); ++i) {
        Message copy = i + 1 < keys.size() ? m : std::move(m);
        if (fault == 2) {
          copy.due = due;
          delayed.emplace_back(keys[i], std::move(copy));
        } else {
          enqueue(keys[i], std::move(copy));
        }
      }
      release_due();
    }
    arrived.notify_all();
    return true;
  }
  void drop_next(const Sender& s, int n) {
    std::lock_guard lock(mutex);
    faults[s].drop = n;
  }
  void delay_next(const Sender& s, int n, std::chrono::nanoseconds d) {
    std::lock_guard lock(mutex);
    faults[s].delay = n;
    faults[s].delay_by = d;
  }
  std::chrono::nanoseconds time() {
    std::lock_guard lock(mutex);
    return now;
  }
  std::uint64_t carried_count() {
    std::lock_guard lock(mutex);
    return carried;
  }
  void set_down(const Sender& s, bool down) {
    {
      std::lock_guard lock(mutex);
      faults[s].down = down;
    }
    arrived.notify_all();
  }

  // Releases delayed messages that are due, in send order.
  void release_due() {
    while (!delayed.empty() && delayed.front().second.due <= now) {
      enqueue(delayed.front().first, std::move(delayed.front().second));
      delayed.pop_front();
    }
  }
  void set_time(std::chrono::nanoseconds t) {
    {
      std::lock_guard lock(mutex);
      now = t;
      release_due();
    }
    arrived.notify_all();
  }

  // Takes the next message for `key` into buf, waiting up to `timeout`.
  // Returns its length or 0; a message too long for buf is dropped.
  std::size_t take(std::uint64_t key, std::span<std::uint8_t> buf, std::chrono::nanoseconds timeout,
                   Extra* extra) {
    std::unique_lock lock(mutex);
    auto& ep = endpoints.at(key);
    auto ready = [&] { return !ep.queue.empty(); };
    if (!ready() && timeout.count() > 0 && !link_down(ep.address))
      arrived.wait_for(lock, timeout, ready);
    if (link_down(ep.address)) ep.queue.clear();
    while (!ep.queue.empty()) {
      Message m = std::move(ep.queue.front());
      ep.queue.pop_front();
      if (m.bytes.size() > buf.size()) {
        ep.counters->rx_dropped.fetch_add(1, std::memory_order_relaxed);
        continue;
      }
      std::copy(m.bytes.begin(), m.bytes.end(), buf.begin());
      if (extra) *extra = m.extra;
      ep.counters->received.fetch_add(1, std::memory_order_relaxed);
      return m.bytes.size();
    }
    return 0;
  }
};

}  // namespace plc::profinet::detail

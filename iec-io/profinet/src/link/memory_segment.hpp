// The shared core of MemoryEthernet and MemoryUdp: a segment of endpoints
// keyed by address, a queue of messages for each, and the fault hooks (drop
// or delay the next n messages from a sender, link down). Private to
// src/link.
//
// A message is copied once into a pooled buffer (message_pool.hpp) that
// every receiver's queue refers to, and copied out by each receiver's
// take(); the queues are rings of buffer numbers (message_ring.hpp). Pool
// and rings only grow past the most messages ever in flight at once, so a
// steady exchange of frames allocates nothing.
//
// Threads: a mutex guards everything, unless the segment's owner declared
// it single-threaded (set_single_threaded(), e.g. the profinet plugin of a
// cell in virtual time, whose scan thread drives every port): then no lock
// is taken, and take() does not wait (no other thread could send what it
// would wait for).
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

#include "message_pool.hpp"
#include "message_ring.hpp"
#include "plc/profinet/link/ethernet_port.hpp"
#include "plc/profinet/link/memory_ethernet.hpp"

namespace plc::profinet::detail {

template <class Sender, class Extra, class Less = std::less<Sender>>
class MemorySegment {
 public:
  // `max_message`: the longest message a port may send (one Ethernet frame,
  // one UDP datagram); the buffers are that long.
  explicit MemorySegment(std::size_t max_message) : pool(max_message) {}

  struct Endpoint {
    Sender address{};
    MessageRing<std::uint32_t> queue;  // buffer numbers, oldest first
    // queue.size(), written under the mutex: a receiver that only looks
    // (timeout 0) at an empty queue returns without taking the mutex, as
    // most polls find nothing. A message queued meanwhile is taken by the
    // next look, as from a socket.
    std::atomic<std::size_t> queued{0};
    LinkCounters* counters = nullptr;
    // Takes only messages to its own address or to a group (an Ethernet
    // port that is not promiscuous); the sender's `to` decides by it.
    bool own_only = false;
  };
  struct Faults {
    int drop = 0;
    int delay = 0;
    std::chrono::nanoseconds delay_by{0};
    bool down = false;
  };
  struct Delayed {
    std::uint64_t receiver = 0;  // endpoint key
    std::uint32_t buffer = 0;
    std::chrono::nanoseconds due{0};
  };

  // The segment's lock: the mutex, or nothing when single-threaded.
  class Lock {
   public:
    explicit Lock(MemorySegment& s) : lock_(s.mutex, std::defer_lock) {
      if (!s.single_threaded.load(std::memory_order_relaxed)) lock_.lock();
    }
    std::unique_lock<std::mutex>& held() { return lock_; }

   private:
    std::unique_lock<std::mutex> lock_;
  };

  std::mutex mutex;
  std::condition_variable arrived;
  // Declared by the segment's owner while no other thread uses the segment;
  // atomic only so that reading it is no data race while it is false.
  std::atomic<bool> single_threaded{false};
  std::map<std::uint64_t, Endpoint> endpoints;  // by endpoint key; nodes stay where they are
  // The same in key order, for send() to go through without walking the tree.
  std::vector<std::pair<std::uint64_t, Endpoint*>> receivers;
  std::map<Sender, Faults, Less> faults;  // by sender address
  MessagePool<Extra> pool;
  MessageRing<Delayed> delayed;  // in send order
  std::chrono::nanoseconds now{0};
  std::uint64_t carried = 0;
  int waiting = 0;  // receivers waiting in take(): send() wakes them

  // The helpers below expect the mutex held.
  bool link_down(const Sender& s) {
    if (faults.empty()) return false;
    auto it = faults.find(s);
    return it != faults.end() && it->second.down;
  }
  // Returns: 0 deliver, 1 dropped, 2 delayed (with `due` set).
  int take_fault(const Sender& s, std::chrono::nanoseconds& due) {
    if (faults.empty()) return 0;
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
  // Queues one reference to `buffer` for `ep`; gives it back if the
  // endpoint's link is down or its queue full.
  void enqueue(Endpoint& ep, std::uint32_t buffer) {
    if (link_down(ep.address)) return pool.release(buffer);  // lost
    if (ep.queue.size() >= kMemoryQueueLimit) {
      ep.counters->rx_dropped.fetch_add(1, std::memory_order_relaxed);
      return pool.release(buffer);
    }
    ep.queue.push_back(buffer);
    ep.queued.store(ep.queue.size(), std::memory_order_relaxed);
  }
  // Sends `bytes` (with `extra`) from `from` to each receiver key that `to`
  // accepts; false if the sender's link is down.
  template <class Accept>
  bool send(const Sender& from, std::uint64_t self, std::span<const std::uint8_t> bytes,
            const Extra& extra, Accept to) {
    bool wake = false;
    {
      Lock lock(*this);
      if (link_down(from)) return false;
      ++carried;
      std::chrono::nanoseconds due{0};
      const int fault = take_fault(from, due);
      if (fault == 1) return true;  // lost on the way, as a real link loses frames
      // The sender's reference keeps the buffer while it is handed out.
      const std::uint32_t buffer = pool.put(bytes, extra);
      for (const auto& [k, ep] : receivers) {
        if (k == self || !to(k, *ep)) continue;
        pool.add_ref(buffer);
        if (fault == 2)
          delayed.push_back({k, buffer, due});
        else
          enqueue(*ep, buffer);
      }
      pool.release(buffer);
      if (!delayed.empty()) release_due();
      wake = waiting > 0;
    }
    if (wake) arrived.notify_all();
    return true;
  }
  void drop_next(const Sender& s, int n) {
    Lock lock(*this);
    faults[s].drop = n;
  }
  void delay_next(const Sender& s, int n, std::chrono::nanoseconds d) {
    Lock lock(*this);
    faults[s].delay = n;
    faults[s].delay_by = d;
  }
  std::chrono::nanoseconds time() {
    Lock lock(*this);
    return now;
  }
  std::uint64_t carried_count() {
    Lock lock(*this);
    return carried;
  }
  void set_down(const Sender& s, bool down) {
    {
      Lock lock(*this);
      faults[s].down = down;
    }
    arrived.notify_all();
  }

  // Releases delayed messages that are due, in send order; one for a
  // receiver that has gone is lost.
  void release_due() {
    while (!delayed.empty() && delayed.front().due <= now) {
      const Delayed d = delayed.front();
      delayed.pop_front();
      auto it = endpoints.find(d.receiver);
      if (it == endpoints.end())
        pool.release(d.buffer);
      else
        enqueue(it->second, d.buffer);
    }
  }
  void set_time(std::chrono::nanoseconds t) {
    {
      Lock lock(*this);
      now = t;
      release_due();
    }
    arrived.notify_all();
  }

  // Adds an endpoint under `key` (not yet there: the caller checked).
  Endpoint& add(std::uint64_t key, const Sender& address, LinkCounters* counters) {
    Endpoint& ep = endpoints[key];
    ep.address = address;
    ep.counters = counters;
    receivers.emplace(std::lower_bound(receivers.begin(), receivers.end(),
                                       std::pair<std::uint64_t, Endpoint*>{key, nullptr}),
                      key, &ep);
    return ep;
  }
  // Removes it, giving back the messages still queued for it.
  void remove(std::uint64_t key) {
    auto it = endpoints.find(key);
    if (it == endpoints.end()) return;
    drain(it->second);
    std::erase_if(receivers, [&](const auto& r) { return r.first == key; });
    endpoints.erase(it);
  }
  void drain(Endpoint& ep) {
    while (!ep.queue.empty()) {
      pool.release(ep.queue.front());
      ep.queue.pop_front();
    }
    ep.queued.store(0, std::memory_order_relaxed);
  }

  // Takes the next message for `ep` into buf, waiting up to `timeout`.
  // Returns its length or 0; a message too long for buf is dropped.
  std::size_t take(Endpoint& ep, std::span<std::uint8_t> buf, std::chrono::nanoseconds timeout,
                   Extra* extra) {
    if (timeout.count() <= 0 && ep.queued.load(std::memory_order_relaxed) == 0) return 0;
    return take_queued(ep, buf, timeout, extra);
  }

 private:
  // The rest of take(), out of line: most polls find nothing and return
  // above without paying for this part's frame.
  [[gnu::noinline]] std::size_t take_queued(Endpoint& ep, std::span<std::uint8_t> buf,
                                            std::chrono::nanoseconds timeout, Extra* extra) {
    Lock lock(*this);
    auto ready = [&] { return !ep.queue.empty(); };
    if (!ready() && timeout.count() > 0 && !link_down(ep.address) && lock.held().owns_lock()) {
      ++waiting;
      arrived.wait_for(lock.held(), timeout, ready);
      --waiting;
    }
    if (link_down(ep.address)) drain(ep);
    while (!ep.queue.empty()) {
      const std::uint32_t buffer = ep.queue.front();
      ep.queue.pop_front();
      ep.queued.store(ep.queue.size(), std::memory_order_relaxed);
      const auto bytes = pool.bytes(buffer);
      if (bytes.size() > buf.size()) {
        ep.counters->rx_dropped.fetch_add(1, std::memory_order_relaxed);
        pool.release(buffer);
        continue;
      }
      std::copy(bytes.begin(), bytes.end(), buf.begin());
      if (extra) *extra = pool.extra(buffer);
      pool.release(buffer);
      ep.counters->received.fetch_add(1, std::memory_order_relaxed);
      return bytes.size();
    }
    return 0;
  }
};

}  // namespace plc::profinet::detail

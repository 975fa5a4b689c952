// The shared core of MemoryEthernet and MemoryUdp: a segment of endpoints
// keyed by address, a queue of messages for each, and the fault hooks (drop
// or delay the next n messages from a sender, link down). Private to
// src/link.
//
// A message is copied once into a pooled buffer (message_pool.hpp) that
// every receiver's queue refers to; a receiver takes it either as a copy
// (take()) or where it lies (view(), no copy): the endpoint then holds the
// buffer until its next take() or view(). The queues are rings of buffer
// numbers (message_ring.hpp). Pool and rings only grow past the most
// messages ever in flight at once, so a steady exchange of frames allocates
// nothing.
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
#include <cstring>
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
    // port that is not promiscuous, every UDP port); the sender's `to`
    // decides by it. Set with set_own_only().
    bool own_only = false;
    // The buffer the last take() or view() handed out, kept (one
    // reference) until the next one: a view stays valid meanwhile.
    std::uint32_t held = MessagePool<Extra>::kNone;
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
  // Endpoints that are not own_only: while there is none, a unicast message
  // can reach only the endpoint under its destination key (send()).
  std::size_t open_endpoints = 0;

  // send()'s `target` when the message has no single destination.
  static constexpr std::uint64_t kEveryone = ~std::uint64_t{0};

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
  [[gnu::always_inline]] void enqueue(Endpoint& ep, std::uint32_t buffer) {
    if (link_down(ep.address)) return pool.release(buffer);  // lost
    if (ep.queue.size() >= kMemoryQueueLimit) {
      ep.counters->rx_dropped.fetch_add(1, std::memory_order_relaxed);
      return pool.release(buffer);
    }
    ep.queue.push_back(buffer);
    ep.queued.store(ep.queue.size(), std::memory_order_relaxed);
  }
  // The endpoint under `key`, or null. A walk, not a tree search: a
  // segment has a handful of endpoints.
  Endpoint* find(std::uint64_t key) {
    for (const auto& [k, ep] : receivers)
      if (k == key) return ep;
    return nullptr;
  }
  // Hands one reference to `buffer` to the receiver `key`: queued now, or
  // (fault 2) at `due`.
  void deliver(Endpoint& ep, std::uint64_t key, std::uint32_t buffer, int fault,
               std::chrono::nanoseconds due) {
    if (fault == 2)
      delayed.push_back({key, buffer, due});
    else
      enqueue(ep, buffer);
  }
  // Sends `bytes` (with `extra`) from `from` to each receiver key that `to`
  // accepts; false if the sender's link is down. `target`: the key of the
  // message's one destination when `to` accepts no other own_only endpoint
  // (a unicast frame, a datagram), else kEveryone. While every endpoint is
  // own_only, that endpoint alone is asked for (the same delivery as
  // asking each with `to`, without walking them).
  template <class Accept>
  bool send(const Sender& from, std::uint64_t self, std::span<const std::uint8_t> bytes,
            const Extra& extra, std::uint64_t target, Accept to) {
    return send_short(self, bytes, extra, target) ||
           send_locked(from, self, bytes, extra, target, to);
  }
  // The common case in virtual time, in short: single-threaded (no lock),
  // no fault ever set (so nothing delayed either, no link down), nobody
  // waiting, one receiver at most. false: not this case, nothing done.
  bool send_short(std::uint64_t self, std::span<const std::uint8_t> bytes, const Extra& extra,
                  std::uint64_t target) {
    if (!single_threaded.load(std::memory_order_relaxed) || !faults.empty() ||
        target == kEveryone || open_endpoints != 0)
      return false;
    ++carried;
    if (target == self) return true;
    Endpoint* ep = find(target);
    if (!ep) return true;
    // enqueue() without its link-down look (no fault set), and no buffer
    // taken for a full queue.
    if (ep->queue.size() >= kMemoryQueueLimit) {
      ep->counters->rx_dropped.fetch_add(1, std::memory_order_relaxed);
      return true;
    }
    ep->queue.push_back(pool.put(bytes, extra));
    ep->queued.store(ep->queue.size(), std::memory_order_relaxed);
    return true;
  }
  // The rest of send(), out of line: the short path above then saves no
  // registers for it.
  template <class Accept>
  [[gnu::noinline]] bool send_locked(const Sender& from, std::uint64_t self,
                                     std::span<const std::uint8_t> bytes, const Extra& extra,
                                     std::uint64_t target, Accept to) {
    bool wake = false;
    {
      Lock lock(*this);
      if (link_down(from)) return false;
      ++carried;
      std::chrono::nanoseconds due{0};
      const int fault = take_fault(from, due);
      if (fault == 1) return true;  // lost on the way, as a real link loses frames
      if (target != kEveryone && open_endpoints == 0) {
        // The sender's reference goes to the one receiver.
        if (target != self)
          if (Endpoint* ep = find(target)) deliver(*ep, target, pool.put(bytes, extra), fault, due);
      } else {
        // The sender's reference keeps the buffer while it is handed out.
        const std::uint32_t buffer = pool.put(bytes, extra);
        for (const auto& [k, ep] : receivers) {
          if (k == self || !to(k, *ep)) continue;
          pool.add_ref(buffer);
          deliver(*ep, k, buffer, fault, due);
        }
        pool.release(buffer);
      }
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
    ++open_endpoints;  // not own_only until set_own_only()
    receivers.emplace(std::lower_bound(receivers.begin(), receivers.end(),
                                       std::pair<std::uint64_t, Endpoint*>{key, nullptr}),
                      key, &ep);
    return ep;
  }
  void set_own_only(Endpoint& ep, bool own_only) {
    if (ep.own_only == own_only) return;
    ep.own_only = own_only;
    if (own_only)
      --open_endpoints;
    else
      ++open_endpoints;
  }
  // Removes it, giving back the messages still queued for it.
  void remove(std::uint64_t key) {
    auto it = endpoints.find(key);
    if (it == endpoints.end()) return;
    set_own_only(it->second, true);
    drain(it->second);
    std::erase_if(receivers, [&](const auto& r) { return r.first == key; });
    endpoints.erase(it);
  }
  void drain(Endpoint& ep) {
    if (ep.held != MessagePool<Extra>::kNone) {
      pool.release(ep.held);
      ep.held = MessagePool<Extra>::kNone;
    }
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
    // The held buffer is ours: read without the lock.
    const auto bytes = next_queued(ep, buf.size(), timeout, extra);
    if (!bytes.empty()) std::memcpy(buf.data(), bytes.data(), bytes.size());
    return bytes.size();
  }
  // The same without the copy: the message where it lies, valid until the
  // endpoint's next take() or view() (or its removal). Empty if none came.
  // A message longer than `max` is dropped, as take() drops one too long
  // for its buffer.
  std::span<const std::uint8_t> view(Endpoint& ep, std::size_t max,
                                     std::chrono::nanoseconds timeout, Extra* extra) {
    if (timeout.count() <= 0) {
      if (ep.queued.load(std::memory_order_relaxed) == 0) return {};
      // Single-threaded and no fault ever set: no lock to take, nothing to
      // wait for, no link down. Inline: the controller and PnDevice call
      // only when queued_count() says a frame is there.
      if (single_threaded.load(std::memory_order_relaxed) && faults.empty())
        return next_ready(ep, max, extra);
    }
    return next_queued(ep, max, timeout, extra);
  }

 private:
  // The rest of take() and view(), out of line: most polls find nothing
  // and return above without paying for this part's frame. Gives back the
  // buffer held since the last call and holds the next message's; its
  // bytes are read under the lock (the slot table may move when another
  // thread's send() grows the pool, the buffer itself does not).
  [[gnu::noinline]] std::span<const std::uint8_t> next_queued(Endpoint& ep, std::size_t max,
                                                              std::chrono::nanoseconds timeout,
                                                              Extra* extra) {
    Lock lock(*this);
    auto ready = [&] { return !ep.queue.empty(); };
    if (!ready() && timeout.count() > 0 && !link_down(ep.address) && lock.held().owns_lock()) {
      ++waiting;
      arrived.wait_for(lock.held(), timeout, ready);
      --waiting;
    }
    if (link_down(ep.address)) drain(ep);
    return next_ready(ep, max, extra);
  }
  // The next message that fits `max`, held (the one held before given
  // back); empty if none.
  std::span<const std::uint8_t> next_ready(Endpoint& ep, std::size_t max, Extra* extra) {
    if (ep.held != MessagePool<Extra>::kNone) {
      pool.release(ep.held);
      ep.held = MessagePool<Extra>::kNone;
    }
    while (!ep.queue.empty()) {
      const std::uint32_t buffer = ep.queue.front();
      ep.queue.pop_front();
      ep.queued.store(ep.queue.size(), std::memory_order_relaxed);
      const auto bytes = pool.bytes(buffer);
      if (bytes.size() > max) {
        ep.counters->rx_dropped.fetch_add(1, std::memory_order_relaxed);
        pool.release(buffer);
        continue;
      }
      if (extra) *extra = pool.extra(buffer);
      ep.held = buffer;
      ep.counters->received.fetch_add(1, std::memory_order_relaxed);
      return bytes;
    }
    return {};
  }
};

}  // namespace plc::profinet::detail

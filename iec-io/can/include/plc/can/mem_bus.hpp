// An in-memory CAN wire for lockstep (virtual-time) tests: every node's
// send() appends to every node's receive queue, its own included, in one
// global order. Thread-safe; no timing (frames arrive at once).
#pragma once

#include <deque>
#include <memory>
#include <mutex>
#include <vector>

#include "plc/can/bus.hpp"

namespace plc::can {

class MemWire : public std::enable_shared_from_this<MemWire> {
 public:
  static std::shared_ptr<MemWire> create() { return std::shared_ptr<MemWire>(new MemWire); }
  std::unique_ptr<Bus> attach();
  // Every frame sent on the wire so far (a capture).
  std::vector<Frame> log() const;

 private:
  MemWire() = default;
  friend class MemBus;
  void broadcast(const Frame& f);
  void detach(class MemBus* n);

  mutable std::mutex mutex_;
  std::vector<class MemBus*> nodes_;
  std::vector<Frame> log_;
};

class MemBus final : public Bus {
 public:
  explicit MemBus(std::shared_ptr<MemWire> w) : wire_(std::move(w)) {}
  ~MemBus() override;
  bool send(const Frame& f) override;
  bool receive(Frame& f) override;
  const BusCounters& counters() const override { return counters_; }

 private:
  friend class MemWire;
  static constexpr std::size_t kQueueLimit = 4096;
  std::shared_ptr<MemWire> wire_;
  std::deque<Frame> queue_;  // guarded by wire_->mutex_
  BusCounters counters_;
};

}  // namespace plc::can

#include "plc/can/mem_bus.hpp"

#include <algorithm>

namespace plc::can {

std::unique_ptr<Bus> MemWire::attach() {
  auto b = std::make_unique<MemBus>(shared_from_this());
  std::lock_guard<std::mutex> lock(mutex_);
  nodes_.push_back(b.get());
  return b;
}

std::vector<Frame> MemWire::log() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return log_;
}

void MemWire::broadcast(const Frame& f) {
  std::lock_guard<std::mutex> lock(mutex_);
  log_.push_back(f);
  for (MemBus* n : nodes_) {
    if (n->queue_.size() >= MemBus::kQueueLimit) {
      ++n->counters_.rx_bad;  // overrun, as a full socket buffer drops
      continue;
    }
    n->queue_.push_back(f);
  }
}

void MemWire::detach(MemBus* n) {
  std::lock_guard<std::mutex> lock(mutex_);
  nodes_.erase(std::remove(nodes_.begin(), nodes_.end(), n), nodes_.end());
}

MemBus::~MemBus() { wire_->detach(this); }

bool MemBus::send(const Frame& f) {
  if (f.len > 8) {
    ++counters_.tx_dropped;
    return false;
  }
  ++counters_.tx;
  wire_->broadcast(f);
  return true;
}

bool MemBus::receive(Frame& f) {
  std::lock_guard<std::mutex> lock(wire_->mutex_);
  if (queue_.empty()) return false;
  f = queue_.front();
  queue_.pop_front();
  ++counters_.rx;
  return true;
}

}  // namespace plc::can

#include "plc/profibus/link/mem_line.hpp"

#include <algorithm>

namespace plc::profibus::link {

std::unique_ptr<Line> MemBus::attach() {
  auto n = std::make_unique<MemLine>(shared_from_this());
  std::lock_guard<std::mutex> lock(mutex_);
  nodes_.push_back(n.get());
  return n;
}

void MemBus::set_cut(bool cut) {
  std::lock_guard<std::mutex> lock(mutex_);
  cut_ = cut;
}

void MemBus::broadcast(MemLine* from, std::span<const std::uint8_t> t) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (cut_) return;
  for (MemLine* n : nodes_) {
    if (n == from) continue;
    if (n->queue_.size() + t.size() > MemLine::kQueueLimit) continue;
    n->queue_.insert(n->queue_.end(), t.begin(), t.end());
  }
}

void MemBus::detach(MemLine* n) {
  std::lock_guard<std::mutex> lock(mutex_);
  nodes_.erase(std::remove(nodes_.begin(), nodes_.end(), n), nodes_.end());
}

MemLine::~MemLine() { bus_->detach(this); }

bool MemLine::send(std::span<const std::uint8_t> telegram) {
  ++counters_.tx_telegrams;
  counters_.tx_bytes += telegram.size();
  bus_->broadcast(this, telegram);
  return true;
}

std::size_t MemLine::receive(std::span<std::uint8_t> buf) {
  std::lock_guard<std::mutex> lock(bus_->mutex_);
  const std::size_t n = std::min(buf.size(), queue_.size());
  std::copy_n(queue_.begin(), n, buf.begin());
  queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(n));
  counters_.rx_bytes += n;
  return n;
}

void MemLine::flush_input() {
  std::lock_guard<std::mutex> lock(bus_->mutex_);
  queue_.clear();
}

}  // namespace plc::profibus::link

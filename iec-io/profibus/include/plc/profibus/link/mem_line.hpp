// An in-memory PROFIBUS line for lockstep (virtual-time) runs: every
// station's send() appends the telegram to every other station's receive
// queue, in one global order. Thread-safe; no timing (the bus timing is
// computed, fdl/timing.hpp, not simulated bit by bit).
#pragma once

#include <deque>
#include <memory>
#include <mutex>
#include <vector>

#include "plc/profibus/link/line.hpp"

namespace plc::profibus::link {

class MemBus : public std::enable_shared_from_this<MemBus> {
 public:
  static std::shared_ptr<MemBus> create() { return std::shared_ptr<MemBus>(new MemBus); }
  std::unique_ptr<Line> attach();
  // Cuts the line (a pulled plug between the master and every slave):
  // telegrams sent while cut reach no one.
  void set_cut(bool cut);

 private:
  MemBus() = default;
  friend class MemLine;
  void broadcast(class MemLine* from, std::span<const std::uint8_t> t);
  void detach(class MemLine* n);

  std::mutex mutex_;
  std::vector<class MemLine*> nodes_;
  bool cut_ = false;
};

class MemLine final : public Line {
 public:
  explicit MemLine(std::shared_ptr<MemBus> b) : bus_(std::move(b)) {}
  ~MemLine() override;
  bool send(std::span<const std::uint8_t> telegram) override;
  std::size_t receive(std::span<std::uint8_t> buf) override;
  void flush_input() override;
  [[nodiscard]] const LineCounters& counters() const override { return counters_; }
  [[nodiscard]] std::string describe() const override { return "in-memory bus"; }

 private:
  friend class MemBus;
  static constexpr std::size_t kQueueLimit = 1 << 16;
  std::shared_ptr<MemBus> bus_;
  std::deque<std::uint8_t> queue_;  // guarded by bus_->mutex_
  LineCounters counters_;
};

}  // namespace plc::profibus::link

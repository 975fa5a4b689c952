// A device with a communication watchdog (see comm_watchdog_probe.cpp).
#pragma once

#include <atomic>

#include "plc/io/device_model.hpp"

namespace plc::io {

class CommWatchdogProbe final : public DeviceModel {
 public:
  explicit CommWatchdogProbe(const ModelParams& p);
  std::size_t input_size() const override { return 4; }
  std::size_t output_size() const override { return 2; }
  void step(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
            std::span<std::uint8_t> to_plc) override;
  void power_cycle() override;

  // Read by a test's thread while, in real time, the sim plugin's thread
  // steps the model: hence atomics (each figure on its own; relaxed is
  // enough, nothing else is published with them).
  [[nodiscard]] bool tripped() const { return tripped_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t exchanges() const {
    return exchanges_.load(std::memory_order_relaxed);
  }
  [[nodiscard]] TIME longest_gap() const {
    return TIME(longest_gap_ns_.load(std::memory_order_relaxed));
  }

 private:
  TIME timeout_;
  std::atomic<bool> tripped_{false};
  std::atomic<std::uint64_t> exchanges_{0};
  std::atomic<std::int64_t> longest_gap_ns_{0};
};

}  // namespace plc::io

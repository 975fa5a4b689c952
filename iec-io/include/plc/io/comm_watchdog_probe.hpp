// A device with a communication watchdog (see comm_watchdog_probe.cpp).
#pragma once

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

  [[nodiscard]] bool tripped() const { return tripped_; }
  [[nodiscard]] std::uint64_t exchanges() const { return exchanges_; }
  [[nodiscard]] TIME longest_gap() const { return longest_gap_; }

 private:
  TIME timeout_;
  bool tripped_ = false;
  std::uint64_t exchanges_ = 0;
  TIME longest_gap_{0};
};

}  // namespace plc::io

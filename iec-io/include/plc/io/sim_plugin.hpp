// The `sim` plugin: hosts device models in-process.
//
// Virtual time: step() advances every model in lockstep (config order). A
// model that couples to other devices (plc/io/device_peers.hpp: the `plant`
// model) sees only the devices listed before it, so within a step it reads
// what they delivered in that step.
// Real time: a thread steps the models every `step` (default 1 ms) against
// CLOCK_MONOTONIC absolute deadlines; latch/publish copy under a mutex held
// for a memcpy, so a scan never waits for a model step longer than one step.
// Virtual time has one thread (the scan's, which also steps): no mutex,
// and the scan copies the devices' buffers itself (Plugin::direct_io).
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "plc/io/plugin.hpp"
#include "plc/io/sim_device.hpp"

namespace plc::io {

class SimPlugin final : public Plugin {
 public:
  ~SimPlugin() override;
  void configure(const ModelParams& params) override;
  DeviceSizes add_device(const DeviceSpec& spec) override;
  void start(ClockMode mode) override;
  void stop() override;
  void step(TIME now, TIME dt) override;
  void latch_inputs(std::size_t device, std::span<std::uint8_t> dst) override;
  void publish_outputs(std::size_t device, std::span<const std::uint8_t> src) override;
  DeviceLink& link(std::size_t device) override { return devices_[device]->link(); }
  // Virtual time: latch and publish are plain copies of the device's
  // buffers (no lock), which never move after add_device().
  std::optional<DirectIo> direct_io(std::size_t device) override;

  // Tests and fault injection reach the models by device name.
  SimDevice* device(const std::string& name);
  [[nodiscard]] TIME step_period() const { return step_; }

 private:
  void run_realtime();

  TIME step_{std::chrono::milliseconds(1)};
  std::vector<std::string> names_;
  std::vector<std::unique_ptr<SimDevice>> devices_;
  std::mutex mutex_;
  bool locking_ = true;  // real time, or not started (tests drive a plugin from threads)
  std::thread thread_;
  std::atomic<bool> running_{false};
};

}  // namespace plc::io

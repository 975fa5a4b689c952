// The `profinet` plugin: a PROFINET IO controller (controller.hpp) on a
// Linux interface (raw Ethernet + UDP 34964) or on an in-memory link
// ("mem:NAME"). Plugin and device keys: docs/config.md.
//
// Real time: the cyclic thread (SCHED_FIFO where permitted) wakes on
// absolute CLOCK_MONOTONIC deadlines every send clock, runs the controller
// (receive, state machines, the frames due) and sleeps again; a missed
// deadline is skipped and counted, never made up with a burst. Virtual
// time: step() runs the controller once per base tick with the virtual
// clock, and the in-memory link (mem:) is declared single-threaded: no lock
// per frame. The scan only copies staging buffers (latch/publish) under the
// mutex the controller runs under (real time).
//
// `simulate: true` (mem: links only) hosts a PnDevice with the device's
// model for every configured device on the same in-memory link, stepped in
// lockstep with the controller: the whole PROFINET exchange runs in virtual
// time, deterministic, inside one plcrun.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "plc/io/device_model.hpp"
#include "plc/io/plugin.hpp"
#include "plc/profinet/controller/controller.hpp"

namespace plc::profinet {

class PnDevice;

// Wake-up figures of the cyclic thread (real time): how late it woke after
// each deadline.
struct WakeStats {
  std::uint64_t wakes = 0;
  std::uint64_t missed = 0;  // deadlines skipped (woke a whole period late or more)
  std::int64_t max_ns = 0;
  std::int64_t sum_ns = 0;
};

class ProfinetPlugin final : public io::Plugin {
 public:
  ProfinetPlugin();
  ~ProfinetPlugin() override;
  void configure(const io::ModelParams& params) override;
  io::DeviceSizes add_device(const io::DeviceSpec& spec) override;
  void start(io::ClockMode mode) override;
  void stop() override;
  void step(TIME now, TIME dt) override;
  void latch_inputs(std::size_t device, std::span<std::uint8_t> dst) override;
  void publish_outputs(std::size_t device, std::span<const std::uint8_t> src) override;
  std::optional<DirectIo> direct_io(std::size_t device) override;
  io::DeviceLink& link(std::size_t device) override { return controller_->link(device); }
  std::string diagnostics(std::size_t device) const override;

  // Tests: the controller and the simulated devices (simulate: true).
  Controller& controller() { return *controller_; }
  PnDevice* simulated(std::size_t device);
  [[nodiscard]] WakeStats wake_stats() const;

 private:
  void open();
  [[gnu::noinline]] void latch_inputs_locked(std::size_t device, std::span<std::uint8_t> dst);
  [[gnu::noinline]] void publish_outputs_locked(std::size_t device,
                                                std::span<const std::uint8_t> src);
  void tick(TIME now);
  [[gnu::noinline]] void tick_locked(TIME now);
  void run_tick(TIME now);
  void run_realtime();

  ControllerConfig cfg_;
  std::string interface_;
  Ipv4 ip_{0xC0A80001};
  bool simulate_ = false;
  bool log_ = true;
  int priority_ = 60;
  std::vector<ControllerDevice> entries_;
  std::vector<std::unique_ptr<io::DeviceModel>> sim_models_;  // simulate: until start()

  std::unique_ptr<EthernetPort> eth_;
  std::unique_ptr<UdpPort> udp_;
  std::vector<std::unique_ptr<EthernetPort>> sim_eth_;
  std::vector<std::unique_ptr<PnDevice>> sim_;
  std::unique_ptr<Controller> controller_;
  mutable std::mutex mutex_;
  // Virtual time: tick() runs on the scan thread alone and takes this lock
  // instead of mutex_. It only keeps diagnostics() (which another thread,
  // e.g. the HMI host's, may call) from reading the controller mid-step;
  // uncontended, a ticket lock costs a few instructions where pthread's
  // lock and unlock cost ~55 per tick, and being first come, first served
  // a virtual-time cell stepping flat out cannot starve that reader.
  // diagnostics() takes it (after mutex_) in either mode.
  mutable std::atomic<std::uint32_t> step_next_{0}, step_serving_{0};
  std::thread thread_;
  std::atomic<bool> running_{false};
  io::ClockMode mode_ = io::ClockMode::Virtual;
  bool single_threaded_link_ = false;  // we declared the mem: link single-threaded
  TIME last_now_{0};
  WakeStats wake_{};  // under mutex_
};

}  // namespace plc::profinet

// The `devicenet` plugin: a DeviceNet scanner (scanner.hpp) on a CAN bus
// (SocketCAN or CAN over UDP). Plugin and device keys: docs/config.md.
//
// Real time: a bus thread waits on the bus (poll() on its descriptor, at
// most 1 ms) and runs the scanner against CLOCK_MONOTONIC. Virtual time:
// step() runs it once per base tick with the virtual clock. Over UDP to
// slaves in other processes, virtual time is not lockstep with them (they
// keep real time), so cells with remote slaves run with clock: realtime.
// latch/publish copy under the mutex the scanner runs under.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "plc/can/bus.hpp"
#include "plc/can/pcap_writer.hpp"
#include "plc/can/udp_bus.hpp"
#include "plc/devicenet/scanner.hpp"
#include "plc/io/plugin.hpp"

namespace plc::devicenet {

class DeviceNetPlugin final : public io::Plugin {
 public:
  ~DeviceNetPlugin() override;
  void configure(const io::ModelParams& params) override;
  io::DeviceSizes add_device(const io::DeviceSpec& spec) override;
  void start(io::ClockMode mode) override;
  void stop() override;
  void step(TIME now, TIME dt) override;
  void latch_inputs(std::size_t device, std::span<std::uint8_t> dst) override;
  void publish_outputs(std::size_t device, std::span<const std::uint8_t> src) override;
  io::DeviceLink& link(std::size_t device) override { return scanner_->link(device); }
  std::string diagnostics(std::size_t device) const override;

 private:
  class CapturingBus;
  void open();
  void tick(TIME now);
  void run_realtime();

  ScannerConfig cfg_;
  std::string bus_spec_;
  bool host_hub_ = false;
  std::string pcap_path_;
  bool log_ = true;
  std::vector<ScanEntry> entries_;

  std::unique_ptr<can::UdpHub> hub_;
  std::unique_ptr<can::Bus> bus_;
  std::unique_ptr<CapturingBus> tap_;
  std::unique_ptr<can::PcapWriter> pcap_;
  std::unique_ptr<Scanner> scanner_;
  can::BusState bus_state_ = can::BusState::ErrorActive;  // the last one logged
  mutable std::mutex mutex_;
  std::thread thread_;
  std::atomic<bool> running_{false};
};

}  // namespace plc::devicenet

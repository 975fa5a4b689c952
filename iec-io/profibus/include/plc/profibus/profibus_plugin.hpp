// The `profibus` plugin: a PROFIBUS-DP master class 1 (dp_master.hpp) on a
// serial line (a USB RS-485 adapter, a UART), a pty, or, with `simulate:
// true`, an in-memory line with a simulated DP slave (dp_slave.hpp) in
// front of every configured device's model. Plugin and device keys:
// docs/config.md.
//
// Real time: the bus thread (SCHED_FIFO where permitted) runs the master:
// it sends a request, waits on the line's descriptor for the answer (or
// the slot time), sends the next one at once, and sleeps between bus
// cycles. Virtual time: step() runs whole bus cycles with the virtual
// clock (the master and the simulated slaves in turns until the line is
// quiet). The scan only copies staging buffers (latch/publish) under the
// mutex the master runs under.
//
// Global_Control for FBs: a record write of index 0xF000 with two bytes
// (Control_Command, Group_Select) on any device of the plugin queues it for
// the next bus cycle.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "plc/io/plugin.hpp"
#include "plc/profibus/link/capture.hpp"
#include "plc/profibus/link/mem_line.hpp"
#include "plc/profibus/master/dp_master.hpp"
#include "plc/profibus/slave/dp_slave.hpp"

namespace plc::profibus {

inline constexpr std::uint16_t kGlobalControlRecord = 0xF000;

struct WakeStats {
  std::uint64_t wakes = 0;
  std::int64_t max_late_ns = 0;
  std::int64_t sum_late_ns = 0;
};

class ProfibusPlugin final : public io::Plugin {
 public:
  ProfibusPlugin();
  ~ProfibusPlugin() override;
  void configure(const io::ModelParams& params) override;
  io::DeviceSizes add_device(const io::DeviceSpec& spec) override;
  void start(io::ClockMode mode) override;
  void stop() override;
  void step(TIME now, TIME dt) override;
  void latch_inputs(std::size_t device, std::span<std::uint8_t> dst) override;
  void publish_outputs(std::size_t device, std::span<const std::uint8_t> src) override;
  io::DeviceLink& link(std::size_t device) override { return master_->link(device); }
  std::string diagnostics(std::size_t device) const override;

  // Tests: the master, the bus parameters, the simulated slaves.
  master::DpMaster& master() { return *master_; }
  [[nodiscard]] const fdl::BusParameters& bus() const { return cfg_.bus; }
  slave::DpSlave* simulated(std::size_t device);
  link::MemBus* memory_bus() { return mem_.get(); }

 private:
  struct Entry {
    std::string name;
    master::SlaveEntry slave;
    std::uint32_t gsd_max_tsdr = 0;  // at the plugin's baud rate (0: none given)
    std::uint32_t min_interval_us = 0;
    slave::SlaveConfig sim;  // simulate: the slave's identity
    std::unique_ptr<io::DeviceModel> model;
  };
  void open();
  void tick(TIME now);
  void serve_records();
  void run_realtime();

  master::MasterConfig cfg_;
  std::uint32_t baud_ = 1500000;
  std::string transport_;
  std::string capture_path_, pcap_path_;
  bool simulate_ = false;
  bool log_ = true;
  int priority_ = 60;
  bool cycle_given_ = false, timeout_given_ = false, retry_limit_given_ = false;
  std::uint8_t retry_limit_ = 1;
  std::vector<Entry> entries_;

  std::unique_ptr<link::Line> line_;
  std::shared_ptr<link::MemBus> mem_;
  std::vector<std::unique_ptr<link::Line>> sim_lines_;
  std::vector<std::unique_ptr<slave::DpSlave>> sim_;
  std::unique_ptr<link::Capture> capture_;
  std::unique_ptr<master::DpMaster> master_;
  io::ClockMode mode_ = io::ClockMode::Virtual;

  mutable std::mutex mutex_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  WakeStats wake_;
};

}  // namespace plc::profibus

// DeviceNet scanner costs (issue 12):
//  * scanner CPU per device per poll cycle: 8 devices on line, the slaves'
//    poll responses fed straight into the scanner's receive queue (no slave
//    work in the figure), one tick = one poll cycle;
//  * the poll cycle 8 devices (8 bytes each way) can have at 500 kbit/s:
//    the bus-time limit (frame bits / baud rate, without and with worst-case
//    bit stuffing) against the software's cost of one cycle (scanner plus
//    the 8 simulated slaves, in-memory bus).
// Prints `name: value unit` lines.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <deque>
#include <iostream>
#include <map>
#include <memory>
#include <vector>

#include "plc/can/mem_bus.hpp"
#include "plc/devicenet/identifiers.hpp"
#include "plc/devicenet/scanner.hpp"
#include "plc/devicenet/slave.hpp"
#include "plc_bench/collector.hpp"

namespace {

using namespace plc;
using namespace std::chrono_literals;
namespace dn = plc::devicenet;

constexpr int kDevices = 8;
constexpr std::size_t kBytes = 8;

class Echo final : public io::DeviceModel {
 public:
  std::size_t input_size() const override { return kBytes; }
  std::size_t output_size() const override { return kBytes; }
  void step(TIME, TIME, std::span<const std::uint8_t> from, std::span<std::uint8_t> to) override {
    std::copy(from.begin(), from.end(), to.begin());
  }
};

// The scanner's view of a bus on which every polled slave answers at once.
class AnsweringBus final : public can::Bus {
 public:
  bool send(const can::Frame& f) override {
    const auto id = dn::decode_id(f.id);
    if (id && id->group == 2 && id->msg == dn::kG2Poll) {
      can::Frame r = f;
      r.id = dn::group1_id(dn::kG1PollResponse, id->mac);
      q_.push_back(r);
    }
    return true;
  }
  bool receive(can::Frame& f) override {
    if (q_.empty()) return false;
    f = q_.front();
    q_.pop_front();
    return true;
  }
  const can::BusCounters& counters() const override { return c_; }

 private:
  std::deque<can::Frame> q_;
  can::BusCounters c_;
};

struct Cell {
  std::shared_ptr<can::MemWire> wire = can::MemWire::create();
  std::unique_ptr<can::Bus> mbus = wire->attach();
  std::unique_ptr<dn::Scanner> scanner;
  std::vector<std::unique_ptr<can::Bus>> sbus;
  std::vector<std::unique_ptr<dn::Slave>> slaves;
  TIME now{0};
  dn::ScannerConfig cfg;

  Cell() {
    cfg.poll_cycle = 10ms;
    cfg.dup_mac_wait = 1ms;
    scanner = std::make_unique<dn::Scanner>(cfg, mbus.get());
    for (int i = 0; i < kDevices; ++i) {
      dn::ScanEntry e;
      e.mac = static_cast<std::uint8_t>(10 + i);
      e.input_size = e.output_size = kBytes;
      e.epr = 100ms;
      scanner->add(e);
      sbus.push_back(wire->attach());
      dn::SlaveConfig s;
      s.mac = e.mac;
      s.dup_mac_wait = 1ms;
      slaves.push_back(std::make_unique<dn::Slave>(s, std::make_unique<Echo>(), *sbus.back()));
    }
    for (int i = 0; i < 2000; ++i) cycle(1ms);
    for (int i = 0; i < kDevices; ++i)
      if (scanner->state(std::size_t(i)) != dn::ScanState::Online) std::abort();
  }
  void cycle(TIME dt) {
    now += dt;
    scanner->tick(now);
    for (auto& s : slaves) s->tick(now);
  }
};

void BM_ScannerOnly(benchmark::State& state) {
  Cell c;
  AnsweringBus bus;
  c.scanner->attach(&bus);
  for (auto _ : state) {
    c.now += c.cfg.poll_cycle;
    c.scanner->tick(c.now);  // takes the 8 responses of the last cycle, sends 8 polls
  }
  if (c.scanner->counters(0).losses != 0) state.SkipWithError("device lost");
}
BENCHMARK(BM_ScannerOnly)->MinTime(0.5);

void BM_PollCycleScannerAndSlaves(benchmark::State& state) {
  Cell c;
  for (auto _ : state) c.cycle(c.cfg.poll_cycle);
}
BENCHMARK(BM_PollCycleScannerAndSlaves)->MinTime(0.5);

// Bits of a CAN 2.0A data frame with n data bytes: SOF, 11-bit id, RTR, IDE,
// r0, DLC (4), data, CRC (15) + delimiter, ACK (2), EOF (7), intermission
// (3) = 47 + 8n; bit stuffing adds at most (34 + 8n - 1) / 4 more.
double frame_bits(std::size_t n, bool worst) {
  const double nominal = 47.0 + 8.0 * double(n);
  return worst ? nominal + double((34 + 8 * n - 1) / 4) : nominal;
}

}  // namespace

int main(int argc, char** argv) {
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  auto get = [&](const char* prefix) { return c.cpu(prefix); };
  const double scanner_ns = get("BM_ScannerOnly");
  const double cycle_ns = get("BM_PollCycleScannerAndSlaves");
  std::printf("devicenet_scanner_cpu_per_device_cycle: %.0f ns\n", scanner_ns / kDevices);
  std::printf("devicenet_scanner_cpu_8dev_cycle: %.2f us\n", scanner_ns / 1e3);
  std::printf("devicenet_sim_cycle_8dev_scanner_and_slaves: %.2f us\n", cycle_ns / 1e3);
  // One poll = command (8 bytes) + response (8 bytes).
  const double baud = 500000.0;
  const double bits = kDevices * (frame_bits(kBytes, false) + frame_bits(kBytes, false));
  const double bits_worst = kDevices * (frame_bits(kBytes, true) + frame_bits(kBytes, true));
  std::printf("devicenet_bus_time_8dev_500k: %.3f ms\n", bits / baud * 1e3);
  std::printf("devicenet_bus_time_8dev_500k_worst_stuffing: %.3f ms\n", bits_worst / baud * 1e3);
  // The shortest cycle: the bus, unless the scanner's CPU is the longer.
  const double achievable_ms = std::max(bits_worst / baud * 1e3, scanner_ns / 1e6);
  std::printf("devicenet_poll_cycle_8dev_500k_achievable: %.3f ms\n", achievable_ms);
  return 0;
}

// PROFIBUS-DP master costs and bus cycle times (issue 24):
//  * master CPU per slave per bus cycle: 8 slaves in Data_Exchange (8 bytes
//    each way), every request answered at once by a line that plays the
//    slaves (no slave work in the figure); one tick = one bus cycle;
//  * one bus cycle of the master and 8 simulated DP slaves on the
//    in-memory line (the plugin's simulate mode);
//  * the bus cycle for N slaves at 1.5 and 12 Mbit/s by the FDL timing
//    (fdl/timing.hpp: 11-bit characters, TSDR, TID1, the token), with the
//    slaves answering at minTSDR (11 bit times, an SPC3) and at the GSD's
//    maxTSDR (worst case);
//  * the bus cycle measured on a pty: the master in this thread, 1 and 8
//    DP slaves in another behind the pty's other side, back-to-back cycles
//    for 2 s (what a Linux pty and two threads of this machine give; the
//    baud rate means nothing on a pty).
// Prints `name: value unit` lines.
#include <benchmark/benchmark.h>
#include <poll.h>

#include <atomic>
#include <cstdio>
#include <deque>
#include <memory>
#include <thread>
#include <vector>

#include "plc/profibus/fdl/timing.hpp"
#include "plc/profibus/link/mem_line.hpp"
#include "plc/profibus/link/serial_line.hpp"
#include "plc/profibus/master/dp_master.hpp"
#include "plc/profibus/slave/dp_slave.hpp"
#include "plc/realtime_thread.hpp"
#include "plc_bench/collector.hpp"

namespace {

using namespace plc;
using namespace plc::profibus;
using namespace std::chrono_literals;

constexpr int kSlaves = 8;
constexpr std::size_t kBytes = 8;

class Echo final : public io::DeviceModel {
 public:
  std::size_t input_size() const override { return kBytes; }
  std::size_t output_size() const override { return kBytes; }
  void step(TIME, TIME, std::span<const std::uint8_t> from, std::span<std::uint8_t> to) override {
    std::copy(from.begin(), from.end(), to.begin());
  }
};

master::SlaveEntry entry(std::uint8_t a) {
  master::SlaveEntry e;
  e.address = a;
  e.prm.ident = 0x5610;
  e.prm.station_status = dp::kPrmLockReq | dp::kPrmWdOn;
  e.prm.wd_fact1 = 100;
  e.cfg = {0xB7};
  e.input_bytes = e.output_bytes = kBytes;
  return e;
}

slave::SlaveConfig slave_cfg(std::uint8_t a) {
  slave::SlaveConfig c;
  c.address = a;
  c.ident = 0x5610;
  c.input_bytes = c.output_bytes = kBytes;
  c.cfg = {0xB7};
  return c;
}

master::MasterConfig master_cfg(TIME cycle) {
  master::MasterConfig m;
  m.address = 1;
  m.bus = fdl::bus_parameters(1500000, {}, kSlaves, kBytes);
  m.bus.gap_factor = 0;
  m.cycle = cycle;
  return m;
}

// The master's view of a line on which every slave answers Data_Exchange at once.
class AnsweringLine final : public link::Line {
 public:
  bool send(std::span<const std::uint8_t> t) override {
    fdl::Telegram q;
    if (fdl::decode(t, q).status != fdl::DecodeStatus::Ok || !q.request() || q.dsap >= 0)
      return true;
    const auto a = fdl::make_data(q.sa, q.da, fdl::kResDataLow, -1, -1, q.du());
    std::array<std::uint8_t, fdl::kMaxTelegram> b{};
    const std::size_t n = fdl::encode(a, b);
    q_.insert(q_.end(), b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
    return true;
  }
  std::size_t receive(std::span<std::uint8_t> buf) override {
    const std::size_t n = std::min(buf.size(), q_.size());
    std::copy_n(q_.begin(), n, buf.begin());
    q_.erase(q_.begin(), q_.begin() + static_cast<std::ptrdiff_t>(n));
    return n;
  }
  const link::LineCounters& counters() const override { return c_; }
  std::string describe() const override { return "answering"; }

 private:
  std::deque<std::uint8_t> q_;
  link::LineCounters c_;
};

struct Cell {
  std::shared_ptr<link::MemBus> bus = link::MemBus::create();
  std::unique_ptr<link::Line> mline = bus->attach();
  std::unique_ptr<master::DpMaster> m;
  std::vector<std::unique_ptr<link::Line>> slines;
  std::vector<std::unique_ptr<slave::DpSlave>> slaves;
  TIME now{0};

  Cell() {
    m = std::make_unique<master::DpMaster>(master_cfg(1ms), mline.get());
    for (int i = 0; i < kSlaves; ++i) {
      const auto a = static_cast<std::uint8_t>(10 + i);
      m->add(entry(a));
      slines.push_back(bus->attach());
      slaves.push_back(
          std::make_unique<slave::DpSlave>(slave_cfg(a), std::make_unique<Echo>(), *slines.back()));
    }
    for (int i = 0; i < 50; ++i) cycle();
    for (int i = 0; i < kSlaves; ++i)
      if (m->state(std::size_t(i)) != master::SlaveState::Online) std::abort();
  }
  void cycle() {
    now += 1ms;
    for (int i = 0; i < 4 * kSlaves; ++i) {
      const auto before = m->telegrams_sent();
      m->tick(now);
      for (auto& s : slaves) s->tick(now);
      if (m->telegrams_sent() == before) break;
    }
  }
};

void BM_MasterOnly(benchmark::State& state) {
  Cell c;
  AnsweringLine line;
  c.m->attach(&line);
  for (auto _ : state) {
    c.now += 1ms;
    for (int i = 0; i < kSlaves + 2; ++i) c.m->tick(c.now);  // 8 requests and answers, the token
  }
  if (c.m->counters(0).losses != 0) state.SkipWithError("slave lost");
}
BENCHMARK(BM_MasterOnly)->MinTime(0.5);

void BM_BusCycleMasterAndSlaves(benchmark::State& state) {
  Cell c;
  for (auto _ : state) c.cycle();
}
BENCHMARK(BM_BusCycleMasterAndSlaves)->MinTime(0.5);

// Back-to-back bus cycles on a pty for `seconds`: the average cycle in us.
double pty_cycle_us(int slaves, double seconds) {
  const std::string path = "/tmp/bench_profibus_pty_" + std::to_string(::getpid());
  auto mline = link::SerialLine::make_pty(path, 1500000);
  auto sline = link::SerialLine::open_tty(path, 1500000);
  // The slaves share the pty's other side through an in-memory line: a
  // bridge station copies bytes both ways.
  auto bus = link::MemBus::create();
  auto bridge = bus->attach();
  std::vector<std::unique_ptr<link::Line>> lines;
  std::vector<std::unique_ptr<slave::DpSlave>> ss;
  for (int i = 0; i < slaves; ++i) {
    lines.push_back(bus->attach());
    ss.push_back(std::make_unique<slave::DpSlave>(slave_cfg(static_cast<std::uint8_t>(10 + i)),
                                                  std::make_unique<Echo>(), *lines.back()));
  }
  std::atomic<bool> run{true};
  std::thread t([&] {
    std::array<std::uint8_t, 512> b{};
    const std::int64_t t0 = mono_ns();
    while (run.load()) {
      pollfd p{sline->fd(), POLLIN, 0};
      (void)poll(&p, 1, 1);
      const std::size_t n = sline->receive(b);
      if (n) bridge->send({b.data(), n});
      for (auto& s : ss) s->tick(TIME(mono_ns() - t0));
      const std::size_t k = bridge->receive(b);
      if (k) sline->send({b.data(), k});
    }
  });
  master::MasterConfig mc = master_cfg(TIME(0));
  mc.min_reply_timeout = 50ms;
  master::DpMaster m(mc, mline.get());
  for (int i = 0; i < slaves; ++i) m.add(entry(static_cast<std::uint8_t>(10 + i)));
  const std::int64_t t0 = mono_ns();
  std::uint64_t start_cycles = 0;
  std::int64_t start_ns = 0;
  bool measuring = false;
  while (mono_ns() - t0 < static_cast<std::int64_t>((seconds + 2) * 1e9)) {
    m.tick(TIME(mono_ns() - t0));
    if (!measuring) {
      bool all = true;
      for (int i = 0; i < slaves; ++i)
        all = all && m.state(std::size_t(i)) == master::SlaveState::Online;
      if (all) {
        measuring = true;
        start_cycles = m.counters().cycles;
        start_ns = mono_ns();
      }
    } else if (mono_ns() - start_ns > static_cast<std::int64_t>(seconds * 1e9)) {
      break;
    }
    pollfd p{mline->fd(), POLLIN, 0};
    (void)poll(&p, 1, 1);
  }
  run = false;
  t.join();
  if (!measuring) return -1;
  const double cycles = double(m.counters().cycles - start_cycles);
  return cycles > 0 ? double(mono_ns() - start_ns) / cycles / 1e3 : -1;
}

}  // namespace

int main(int argc, char** argv) {
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  const double master_ns = c.cpu("BM_MasterOnly");
  const double cycle_ns = c.cpu("BM_BusCycleMasterAndSlaves");
  std::printf("profibus_master_cpu_per_slave_cycle: %.0f ns\n", master_ns / kSlaves);
  std::printf("profibus_master_cpu_8slaves_cycle: %.2f us\n", master_ns / 1e3);
  std::printf("profibus_sim_cycle_8slaves_master_and_slaves: %.2f us\n", cycle_ns / 1e3);
  for (const std::uint32_t baud : {1500000u, 12000000u}) {
    const auto* prof = fdl::baud_profile(baud);
    for (const std::size_t n : {1u, 8u, 32u}) {
      const auto p = fdl::bus_parameters(baud, {}, n, kBytes);
      const double best = double(fdl::bus_cycle_bits(p, n, kBytes, kBytes, p.min_tsdr));
      const double worst = double(fdl::bus_cycle_bits(p, n, kBytes, kBytes, p.max_tsdr));
      std::printf(
          "profibus_bus_cycle_%zuslaves_%s_computed: %.1f us (slaves at maxTSDR: %.1f us)\n", n,
          prof->gsd_suffix, best * 1e6 / baud, worst * 1e6 / baud);
    }
  }
  for (const int n : {1, 8}) {
    const double us = pty_cycle_us(n, 2.0);
    std::printf("profibus_bus_cycle_%dslaves_pty_measured: %.1f us\n", n, us);
  }
  return 0;
}

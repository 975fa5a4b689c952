// PROFINET IO controller costs (issue 11):
//  * controller CPU time per device per 1 ms cycle: N devices (HIWIN E1,
//    telegram 111) brought on line over the in-memory hub; then the
//    controller is moved to a feed port (FeedPort below) that hands it the
//    devices' N input frames of the cycle (cycle counters advanced) and
//    takes its N output frames without copying them anywhere. The figure is
//    the thread CPU time of Controller::poll() alone (manual time): neither
//    the simulated devices nor the hub are in it. (The hub shows every
//    port every frame, so with the hub in the loop the figure grew as N^2:
//    0.78 / 3.7 / 15.6 us per device at 1 / 16 / 64 devices when it still
//    copied each frame into a new vector per port, almost all of it the
//    hub's; bench_pn_wire's pn_hub_cyclic_frame is the hub's own cost.)
//  * how many devices one core sustains at 1 ms: 1 ms over that cost, and a
//    real-time run of the plugin's cyclic thread with 16 simulated devices
//    on the same core's thread (controller + devices) counting late output
//    frames and lost input frames;
//  * wake-up latency of the cyclic thread (SCHED_FIFO where permitted)
//    next to cyclictest's, in the same run.
// Prints `name: value unit` lines.
#include <benchmark/benchmark.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <iostream>
#include <memory>
#include <thread>
#include <vector>

#include "hiwin_e1/hiwin_e1_model.hpp"
#include "plc/profinet/controller/controller.hpp"
#include "plc/profinet/controller/profinet_plugin.hpp"
#include "plc/profinet/description/builtin_descriptions.hpp"
#include "plc/profinet/device/pn_device.hpp"
#include "plc/profinet/link/memory_ethernet.hpp"
#include "plc/profinet/link/memory_udp.hpp"
#include "plc/profinet/wire/cyclic.hpp"
#include "plc/profinet/wire/ethernet.hpp"
#include "plc_bench/collector.hpp"

namespace {

using namespace plc::profinet;
using namespace std::chrono_literals;
namespace io = plc::io;

// The controller's Ethernet port in the measurement: receive() hands out
// the frames of the present cycle one by one, send() only counts (what a
// raw socket's send costs is the kernel's, not the controller's).
class FeedPort final : public EthernetPort {
 public:
  explicit FeedPort(Mac mac) : mac_(mac) {}
  Mac mac() const override { return mac_; }
  bool send(std::span<const std::uint8_t>) override { return ++sent, true; }
  std::size_t receive(std::span<std::uint8_t> buf, std::chrono::nanoseconds) override {
    if (!frames || next >= frames->size()) return 0;
    const auto& f = (*frames)[next++];
    std::copy(f.begin(), f.end(), buf.begin());
    return f.size();
  }
  const std::vector<std::vector<std::uint8_t>>* frames = nullptr;
  std::size_t next = 0;
  std::uint64_t sent = 0;

 private:
  Mac mac_;
};

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

struct Rig {
  explicit Rig(int n) {
    ctrl_eth = hub.port(Mac{0x02, 0, 0, 0, 0, 1});
    ctrl_udp = net.port(*parse_ipv4("192.168.0.1"), kPnioRpcPort);
    ctrl = std::make_unique<Controller>(ControllerConfig{}, ctrl_eth.get(), ctrl_udp.get());
    tap = hub.port(Mac{0x02, 0, 0, 0, 0xEE, 0xEE});
    io::ModelParams p;
    p.set("telegram", "111");
    for (int i = 0; i < n; ++i) {
      DeviceDescription d = builtin_description("hiwin_e1", p);
      d.station_name = "axis-" + std::to_string(i);
      d.ip = Ipv4{0xC0A80100u + static_cast<std::uint32_t>(i)};
      ControllerDevice c;
      c.name = d.station_name;
      c.desc = d;
      ctrl->add(c);
      eths.push_back(hub.port(Mac{0x02, 0, 0, 1, 0, static_cast<std::uint8_t>(i)}));
      PnDeviceConfig dc;
      dc.description = d;
      MemoryUdp u = net;
      devs.push_back(std::make_unique<PnDevice>(
          dc, std::make_unique<plc::sim::HiwinE1Model>(plc::sim::HiwinE1Config{}), *eths.back(),
          [u](Ipv4 ip) mutable { return u.port(ip, kPnioRpcPort); }));
    }
    for (int k = 0; k < 3000; ++k) {
      cycle();
      bool all = true;
      for (int i = 0; i < n; ++i) all = all && ctrl->state(std::size_t(i)) == ArState::Online;
      if (all && k > 100) break;
    }
    for (int i = 0; i < n; ++i)
      if (ctrl->state(std::size_t(i)) != ArState::Online) std::abort();
    // One input frame of each device, to feed in without the devices.
    std::array<std::uint8_t, 1600> b{};
    while (tap->receive(b, 0ns) > 0) {
    }
    cycle();
    for (std::size_t len; (len = tap->receive(b, 0ns)) > 0;) {
      PnFrameView v;
      if (decode_pn_frame(std::span(b).first(len), v) && is_rt_class1(v.frame_id) &&
          v.src != ctrl_eth->mac())
        frames.emplace_back(b.begin(), b.begin() + static_cast<long>(len));
    }
    if (frames.size() != static_cast<std::size_t>(n)) std::abort();
    // From here on the controller talks to the feed port only.
    feed = std::make_unique<FeedPort>(ctrl_eth->mac());
    feed->frames = &frames;
    ctrl->attach(feed.get(), ctrl_udp.get());
  }
  void cycle() {
    now += 1ms;
    ctrl->poll(now);
    for (auto& d : devs) d->poll(now);
    ctrl->poll(now);
  }
  // Controller alone: the devices' frames of this cycle made ready (not
  // timed), then one poll (timed). Returns its thread CPU seconds.
  double controller_cycle() {
    now += 1ms;
    for (auto& f : frames) {
      const std::size_t at = f.size() - 4;  // CycleCounter
      const auto c = static_cast<std::uint16_t>(((f[at] << 8) | f[at + 1]) + 32);
      f[at] = static_cast<std::uint8_t>(c >> 8);
      f[at + 1] = static_cast<std::uint8_t>(c);
    }
    feed->next = 0;
    const double t0 = thread_cpu_seconds();
    ctrl->poll(now);
    return thread_cpu_seconds() - t0;
  }

  MemoryEthernet hub;
  MemoryUdp net;
  std::unique_ptr<EthernetPort> ctrl_eth, tap;
  std::unique_ptr<FeedPort> feed;
  std::unique_ptr<UdpPort> ctrl_udp;
  std::unique_ptr<Controller> ctrl;
  std::vector<std::unique_ptr<EthernetPort>> eths;
  std::vector<std::unique_ptr<PnDevice>> devs;
  std::vector<std::vector<std::uint8_t>> frames;
  plc::TIME now{0};
};

void BM_ControllerCycle(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  Rig r(n);
  const std::uint64_t sent0 = r.feed->sent;
  std::int64_t cycles = 0;
  for (auto _ : state) {
    state.SetIterationTime(r.controller_cycle());
    ++cycles;
  }
  // Every cycle took every input frame and sent every output frame.
  if (r.feed->sent - sent0 != std::uint64_t(cycles) * std::uint64_t(n))
    state.SkipWithError("not one output frame per device per cycle");
  for (int i = 0; i < n; ++i)
    if (r.ctrl->state(std::size_t(i)) != ArState::Online ||
        r.ctrl->counters(std::size_t(i)).losses != 0 ||
        r.ctrl->counters(std::size_t(i)).bad_total() != 0)
      state.SkipWithError("device lost or bad frames");
}
BENCHMARK(BM_ControllerCycle)->Arg(1)->Arg(16)->Arg(64)->UseManualTime()->MinTime(0.5);

// The plugin in real time on mem: with `n` simulated devices, for `ms`.
WakeStats run_plugin(int n, int ms, DeviceCounters& worst) {
  ProfinetPlugin plugin;
  io::ModelParams p;
  p.set("interface", "mem:bench-" + std::to_string(n));
  p.set("simulate", "true");
  p.set("log", "false");
  plugin.configure(p);
  for (int i = 0; i < n; ++i) {
    io::ModelParams d;
    d.set("telegram", "111");
    d.set("station_name", "axis-" + std::to_string(i));
    d.set("ip", "192.168.1." + std::to_string(10 + i));
    plugin.add_device({"axis" + std::to_string(i), "hiwin_e1", d});
  }
  plugin.start(io::ClockMode::RealTime);
  std::this_thread::sleep_for(std::chrono::milliseconds(ms));  // the measured run itself
  plugin.stop();
  worst = {};
  for (int i = 0; i < n; ++i) {
    const auto& c = plugin.controller().counters(std::size_t(i));
    worst.late = std::max(worst.late, c.late);
    worst.lost = std::max(worst.lost, c.lost);
    worst.losses = std::max(worst.losses, c.losses);
    worst.frames_out = std::max(worst.frames_out, c.frames_out);
  }
  return plugin.wake_stats();
}

}  // namespace

int main(int argc, char** argv) {
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  // Manual time: the controller thread's CPU time in poll().
  const double one = c.wall("BM_ControllerCycle/1/");
  const double sixteen = c.wall("BM_ControllerCycle/16/");
  const double sixtyfour = c.wall("BM_ControllerCycle/64/");
  std::printf("profinet_controller_cpu_per_device_cycle_1dev: %.0f ns\n", one);
  std::printf("profinet_controller_cpu_per_device_cycle_16dev: %.0f ns\n", sixteen / 16);
  std::printf("profinet_controller_cpu_per_device_cycle_64dev: %.0f ns\n", sixtyfour / 64);
  if (sixtyfour > 0)
    std::printf("profinet_devices_per_core_1ms_by_cpu: %.0f devices\n", 1e6 / (sixtyfour / 64));

  DeviceCounters w;
  const WakeStats s16 = run_plugin(16, 3000, w);
  std::printf("profinet_rt_16dev_3s_frames_out: %llu frames\n",
              static_cast<unsigned long long>(w.frames_out));
  std::printf("profinet_rt_16dev_3s_late_frames_max: %llu frames\n",
              static_cast<unsigned long long>(w.late));
  std::printf("profinet_rt_16dev_3s_lost_frames_max: %llu frames\n",
              static_cast<unsigned long long>(w.lost));
  std::printf("profinet_rt_16dev_3s_losses_max: %llu\n", static_cast<unsigned long long>(w.losses));
  std::printf("profinet_rt_16dev_missed_deadlines: %llu\n",
              static_cast<unsigned long long>(s16.missed));

  const WakeStats s1 = run_plugin(1, 3000, w);
  if (s1.wakes > 0) {
    std::printf("profinet_cyclic_wake_latency_avg: %.1f us\n",
                double(s1.sum_ns) / double(s1.wakes) / 1e3);
    std::printf("profinet_cyclic_wake_latency_max: %.1f us\n", double(s1.max_ns) / 1e3);
  }
  // cyclictest, same machine, same run: one SCHED_FIFO thread at the same
  // priority and period (1 ms), 3000 loops.
  if (FILE* f = popen("cyclictest -q -m -p 60 -i 1000 -l 3000 2>/dev/null", "r")) {
    char line[512];
    while (std::fgets(line, sizeof line, f)) {
      unsigned long mn = 0, av = 0, mx = 0;
      const char* t = std::strstr(line, "Min:");
      if (t && std::sscanf(t, "Min: %lu Act: %*u Avg: %lu Max: %lu", &mn, &av, &mx) == 3) {
        std::printf("cyclictest_wake_latency_avg: %lu us\n", av);
        std::printf("cyclictest_wake_latency_max: %lu us\n", mx);
      }
    }
    pclose(f);
  }
  return 0;
}

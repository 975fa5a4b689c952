// The `profinet` plugin itself: its config checks, and its cyclic thread in
// real time (mem: link with simulated devices) with the scan side copying
// staging buffers concurrently (the test TSan runs for the plugin's thread).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "plc/profinet/controller/profinet_plugin.hpp"
#include "plc/profinet/device/pn_device.hpp"
#include "plc/profinet/link/open_link.hpp"

namespace {

using namespace plc::profinet;
namespace io = plc::io;

io::ModelParams params(std::initializer_list<std::pair<const char*, const char*>> kv) {
  io::ModelParams p;
  for (auto [k, v] : kv) p.set(k, v);
  return p;
}

std::string config_error(const io::ModelParams& p) {
  ProfinetPlugin plugin;
  try {
    plugin.configure(p);
  } catch (const io::ParamError& e) {
    return e.key + ": " + e.what();
  }
  return "";
}

TEST(ProfinetPlugin, ConfigErrorsNameTheKey) {
  EXPECT_NE(config_error(params({})).find("interface: "), std::string::npos);
  EXPECT_NE(
      config_error(params({{"interface", "mem:x"}, {"send_clock", "3ms"}})).find("send_clock: "),
      std::string::npos);
  EXPECT_NE(config_error(params({{"interface", "mem:x"}, {"ip", "1.2.3"}})).find("ip: "),
            std::string::npos);
  EXPECT_NE(config_error(params({{"interface", "eth0"}, {"simulate", "true"}})).find("simulate: "),
            std::string::npos);
  EXPECT_NE(config_error(params({{"interface", "mem:x"}, {"bogus", "1"}})).find("bogus"),
            std::string::npos);
  EXPECT_EQ(config_error(params({{"interface", "mem:x"}, {"send_clock", "250us"}})), "");
}

TEST(ProfinetPlugin, DeviceErrorsNameTheKey) {
  ProfinetPlugin plugin;
  plugin.configure(params({{"interface", "mem:plugin-dev-errors"}, {"simulate", "true"}}));
  io::DeviceSpec d{
      "conveyor", "hiwin_e1",
      params({{"telegram", "111"}, {"station_name", "conveyor"}, {"ip", "192.168.0.10"}})};
  EXPECT_EQ(plugin.add_device(d).input_bytes, 24u);
  io::DeviceSpec same_ip{"other", "hiwin_e1",
                         params({{"station_name", "other"}, {"ip", "192.168.0.10"}})};
  try {
    plugin.add_device(same_ip);
    FAIL() << "duplicate IP accepted";
  } catch (const io::ParamError& e) {
    EXPECT_EQ(e.key, "ip");
  }
  io::DeviceSpec typo{"x", "hiwin_e1",
                      params({{"station_name", "x"}, {"ip", "192.168.0.12"}, {"telegramm", "3"}})};
  try {
    plugin.add_device(typo);
    FAIL() << "unknown key accepted";
  } catch (const io::ParamError& e) {
    EXPECT_EQ(e.key, "telegramm");
  }
}

// Real time: the plugin's own thread brings the simulated device on line
// and exchanges data while this thread latches and publishes like a scan.
TEST(ProfinetPlugin, RealTimeThreadExchangesDataWhileTheScanCopies) {
  ProfinetPlugin plugin;
  plugin.configure(params(
      {{"interface", "mem:plugin-rt"}, {"simulate", "true"}, {"log", "false"}, {"retry", "10ms"}}));
  plugin.add_device(
      {"conveyor", "hiwin_e1",
       params({{"telegram", "111"}, {"station_name", "conveyor"}, {"ip", "192.168.0.10"}})});
  plugin.start(io::ClockMode::RealTime);
  std::array<std::uint8_t, 24> in{}, out{};
  bool online = false;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (int i = 0; i < 100000 && std::chrono::steady_clock::now() < end; ++i) {
    plugin.latch_inputs(0, in);
    out[1] = static_cast<std::uint8_t>(i);
    plugin.publish_outputs(0, out);
    (void)plugin.diagnostics(0);
    if (plugin.link(0).live_state() == io::DeviceState::Online) {
      online = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // a scan period
  }
  EXPECT_TRUE(online) << plugin.diagnostics(0);
  for (int i = 0; i < 50; ++i) {
    plugin.latch_inputs(0, in);
    plugin.publish_outputs(0, out);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  plugin.stop();
  const std::string d = plugin.diagnostics(0);
  EXPECT_NE(d.find("cyclic thread wake-ups"), std::string::npos) << d;
  EXPECT_EQ(plugin.link(0).live_state(), io::DeviceState::Offline) << "released on stop";
  EXPECT_GT(plugin.wake_stats().wakes, 10u);
}

// Virtual time: the runtime's scan thread steps every plugin, so the
// plugin declares its mem: link single-threaded (no lock per frame) from
// start() to stop(); in real time (its cyclic thread) the link keeps its
// lock.
TEST(ProfinetPlugin, VirtualTimeDeclaresTheMemoryLinkSingleThreaded) {
  for (const io::ClockMode mode : {io::ClockMode::Virtual, io::ClockMode::RealTime}) {
    const bool virtual_time = mode == io::ClockMode::Virtual;
    ProfinetPlugin plugin;
    plugin.configure(
        params({{"interface", "mem:plugin-one-thread"}, {"simulate", "true"}, {"log", "false"}}));
    plugin.add_device(
        {"conveyor", "hiwin_e1",
         params({{"telegram", "111"}, {"station_name", "conveyor"}, {"ip", "192.168.0.10"}})});
    plugin.start(mode);
    EXPECT_EQ(memory_ethernet("plugin-one-thread").single_threaded(), virtual_time);
    EXPECT_EQ(memory_udp("plugin-one-thread").single_threaded(), virtual_time);
    if (virtual_time) {
      for (int ms = 1; ms <= 200; ++ms) plugin.step(std::chrono::milliseconds(ms), {});
      EXPECT_EQ(plugin.link(0).live_state(), io::DeviceState::Online) << plugin.diagnostics(0);
    }
    plugin.stop();
    EXPECT_FALSE(memory_ethernet("plugin-one-thread").single_threaded());
    EXPECT_FALSE(memory_udp("plugin-one-thread").single_threaded());
    if (virtual_time) {
      EXPECT_EQ(plugin.link(0).live_state(), io::DeviceState::Offline) << plugin.diagnostics(0);
    }
  }
}

// Virtual time: latch_inputs()/publish_outputs() only copy the controller's
// staging buffers, so the plugin offers them for the scan to copy itself
// (Plugin::direct_io): the device's sizes, where they stay, the same bytes
// the copies give. Real time: not offered (the copies take the mutex).
TEST(ProfinetPlugin, VirtualTimeOffersTheStagingBuffersForDirectCopies) {
  for (const io::ClockMode mode : {io::ClockMode::Virtual, io::ClockMode::RealTime}) {
    ProfinetPlugin plugin;
    plugin.configure(
        params({{"interface", "mem:plugin-direct"}, {"simulate", "true"}, {"log", "false"}}));
    const io::DeviceSizes sizes = plugin.add_device(
        {"conveyor", "hiwin_e1",
         params({{"telegram", "111"}, {"station_name", "conveyor"}, {"ip", "192.168.0.10"}})});
    plugin.start(mode);
    const auto direct = plugin.direct_io(0);
    if (mode == io::ClockMode::RealTime) {
      EXPECT_FALSE(direct.has_value());
      plugin.stop();
      continue;
    }
    ASSERT_TRUE(direct.has_value());
    EXPECT_EQ(direct->in.size(), sizes.input_bytes);
    EXPECT_EQ(direct->out.size(), sizes.output_bytes);
    std::vector<std::uint8_t> in(sizes.input_bytes), out(sizes.output_bytes);
    for (int ms = 1; ms <= 300; ++ms) {
      plugin.latch_inputs(0, in);
      ASSERT_TRUE(std::equal(in.begin(), in.end(), direct->in.begin())) << "ms " << ms;
      out[1] = static_cast<std::uint8_t>(ms);
      direct->out[1] = static_cast<std::uint8_t>(ms + 1);
      plugin.publish_outputs(0, out);  // writes where the direct copy writes
      ASSERT_EQ(direct->out[1], static_cast<std::uint8_t>(ms));
      plugin.step(std::chrono::milliseconds(ms), {});
      const auto again = plugin.direct_io(0);
      ASSERT_EQ(again->in.data(), direct->in.data()) << "the staging buffers never move";
      ASSERT_EQ(again->out.data(), direct->out.data());
    }
    EXPECT_EQ(plugin.link(0).live_state(), io::DeviceState::Online) << plugin.diagnostics(0);
    plugin.stop();
  }
}

// Virtual time: the scan thread steps without the mutex; diagnostics()
// from another thread (the HMI host's) still never reads mid-step (TSan
// checks this test).
TEST(ProfinetPlugin, VirtualTimeDiagnosticsFromAnotherThreadWhileStepping) {
  ProfinetPlugin plugin;
  plugin.configure(
      params({{"interface", "mem:plugin-diag"}, {"simulate", "true"}, {"log", "false"}}));
  plugin.add_device(
      {"conveyor", "hiwin_e1",
       params({{"telegram", "111"}, {"station_name", "conveyor"}, {"ip", "192.168.0.10"}})});
  plugin.start(io::ClockMode::Virtual);
  std::atomic<bool> done{false};
  std::atomic<std::size_t> reads{0};
  std::thread reader([&] {
    while (!done.load()) {
      if (!plugin.diagnostics(0).empty()) ++reads;
      std::this_thread::yield();
    }
  });
  // At least 300 ms, and on until the reader has read a while alongside
  // (or 10 s have passed: a loaded machine may rarely run the reader).
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (int ms = 1; ms <= 300 || (reads.load() < 50 && std::chrono::steady_clock::now() < end); ++ms)
    plugin.step(std::chrono::milliseconds(ms), {});
  done = true;
  reader.join();
  EXPECT_GT(reads.load(), 0u);
  EXPECT_EQ(plugin.link(0).live_state(), io::DeviceState::Online) << plugin.diagnostics(0);
  plugin.stop();
}

}  // namespace

// Test rig: a NORD_SAFE_IO block bound to a simulated NORD F-device, run in
// lockstep virtual time (1 ms per scan): scan = FB call, then device step.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>

#include "plc/fb/safety/nord_safe_io.hpp"
#include "plc/io/sim_device.hpp"
#include "plc/scan_context.hpp"
#include "plc/sim/nord_profisafe_model.hpp"

namespace safety_test {

using namespace std::chrono_literals;

// A fully enabled device: SI1/SI2, SO1-3, clocks, encoder, all functions.
inline std::map<std::string, std::string> default_device_params() {
  return {
      {"dip_address", "1"}, {"p840", "305441741"},  // 0x1234ABCD
      {"p802_1", "1"},      {"p802_2", "1"},       {"p802_3", "1"},   {"p802_4", "1"},
      {"p802_5", "1"},      {"p802_6", "1"},       {"p802_7", "1"},   {"p810", "1"},
      {"p820_1", "1"},      {"p820_2", "1"},       {"p820_3", "1"},   {"p820_4", "1"},
      {"p820_5", "1"},      {"p823_1", "100"},     {"p823_2", "500"}, {"p823_3", "1000"},
      {"p823_4", "1500"},   {"p823_5", "2000"},    {"p823_6", "0"},   {"p823_7", "50"},
      {"p824_1", "100"},    {"p824_2", "100"},     {"p824_3", "100"},
  };
}

using Params = std::map<std::string, std::string>;

// Deterministic randomness for randomized tests: std::mt19937_64, whose
// output sequence the standard fixes; below(n) is in [0, n).
struct Random {
  explicit Random(std::uint64_t seed) : gen(seed) {}
  int below(int n) { return static_cast<int>(gen() % static_cast<std::uint64_t>(n)); }
  std::mt19937_64 gen;
};

struct Rig {
  explicit Rig(Params overrides = {}) {
    auto kv = default_device_params();
    for (auto& [k, v] : overrides) kv[k] = v;
    plc::io::ModelParams p;
    for (auto& [k, v] : kv) p.set(k, v);
    auto m = std::make_unique<plc::sim::NordProfisafeModel>(p);
    model = m.get();
    dev = std::make_unique<plc::io::SimDevice>(std::move(m));
    dev->bind(io.FMOD.port);
    io.FMOD.F_Dest_Add = 1;
    io.FMOD.F_Source_Add = 10;
    io.FMOD.F_WD_Time = 100;
    io.FMOD.F_iPar_CRC = 0x1234ABCD;
  }

  void scan(int n = 1) {
    for (int i = 0; i < n; ++i) {
      ctx.now += dt;
      io(ctx);
      dev->step(ctx.now, dt);
      ++ctx.cycle;
    }
  }
  // Device runs, host not called (frozen F-host).
  void device_only(int n) {
    for (int i = 0; i < n; ++i) {
      ctx.now += dt;
      dev->step(ctx.now, dt);
      ++ctx.cycle;
    }
  }
  // Scans until pred() or max scans; returns scans taken, -1 if never.
  template <class P>
  int scan_until(P pred, int max) {
    for (int i = 1; i <= max; ++i) {
      scan();
      if (pred()) return i;
    }
    return -1;
  }
  bool running() const { return io.FMOD.STATE == plc::safety::FHostState::Run && !io.QBAD; }
  // Start-up to Run with SO1 commanded on.
  void start() {
    io.OSSD1 = true;
    scan(10);
  }
  void ack() {
    io.FMOD.ACK_REI = true;
    scan();
    io.FMOD.ACK_REI = false;
    scan();
  }
  // Host side safe: QBAD, inputs all 0, no value status; device side: SOs off.
  bool all_safe() const {
    for (auto b : io.FMOD.IN_DATA)
      if (b != 0) return false;
    for (auto b : io.FMOD.VS_IN)
      if (b != 0) return false;
    return io.QBAD && !model->ossd(0) && !model->ossd(1) && !model->ossd(2);
  }

  plc::safety::NORD_SAFE_IO io;
  plc::sim::NordProfisafeModel* model = nullptr;
  std::unique_ptr<plc::io::SimDevice> dev;
  plc::ScanContext ctx{};
  plc::TIME dt = 1ms;
};

}  // namespace safety_test

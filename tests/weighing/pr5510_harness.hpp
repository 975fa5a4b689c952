// Test harness: a simulated PR5510 hosted in a SimDevice, stepped in
// virtual time 1 ms at a time, with raw access to both windows.
#pragma once

#include <chrono>
#include <memory>

#include "plc/io/sim_device.hpp"
#include "pr5510/pr5510_model.hpp"

namespace wtest {

using namespace std::chrono_literals;

// A quiet device: no noise, no flow variation (exact values in tests).
inline plc::sim::Pr5510Config quiet_config(plc::weighing::Bus bus = plc::weighing::Bus::Profibus) {
  plc::sim::Pr5510Config c;
  c.bus = bus;
  c.filling.noise_kg = 0;
  c.filling.impact_noise = 0;
  c.filling.flow_variation = 0;
  c.filling.flow_wander = 0;
  return c;
}

struct Harness {
  explicit Harness(const plc::sim::Pr5510Config& c)
      : dev(std::make_unique<plc::sim::Pr5510Model>(c)),
        model(static_cast<plc::sim::Pr5510Model&>(dev.model())) {}

  // Advance the device by `ms` milliseconds, 1 ms per step.
  void run(std::chrono::milliseconds ms) {
    for (std::int64_t i = 0; i < ms.count(); ++i) {
      now += 1ms;
      dev.step(now, 1ms);
    }
  }
  std::span<std::uint8_t> w() { return dev.outputs(); }
  std::span<std::uint8_t> r() { return dev.inputs(); }

  plc::io::SimDevice dev;
  plc::sim::Pr5510Model& model;
  plc::TIME now{};
};

}  // namespace wtest

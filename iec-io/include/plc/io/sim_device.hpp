// One simulated device with its cyclic buffers and acyclic queue: the unit
// the sim plugin is built from, and the harness FB tests use directly:
//
//   plc::io::SimDevice dev(std::make_unique<MyModel>(params));
//   dev.bind(fb.port);                 // FB reads/writes dev's buffers
//   for (...) { fb(ctx); dev.step(ctx.now, 1ms); }
//
// Acyclic requests submitted during a scan are answered at the next step(),
// which is how the lockstep plugin answers them too: one step of latency,
// deterministic.
#pragma once

#include <memory>
#include <vector>

#include "plc/io/device_link.hpp"
#include "plc/io/device_model.hpp"
#include "plc/io/device_port.hpp"

namespace plc::io {

class SimDevice {
 public:
  explicit SimDevice(std::unique_ptr<DeviceModel> model);

  // Answer queued records, then step the model with the PLC's outputs.
  void step(TIME now, TIME dt);

  // Bind an FB's port straight to this device's buffers (tests).
  void bind(DevicePort& port) { port.bind(inputs_, outputs_, &link_); }

  DeviceModel& model() { return *model_; }
  DeviceLink& link() { return link_; }
  std::span<std::uint8_t> inputs() { return inputs_; }    // device -> PLC
  std::span<std::uint8_t> outputs() { return outputs_; }  // PLC -> device

 private:
  void serve_records();

  std::unique_ptr<DeviceModel> model_;
  std::vector<std::uint8_t> inputs_, outputs_, silent_sink_;
  DeviceLink link_;
};

}  // namespace plc::io

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
  // Inline: the sim plugin steps every device every cycle, and the usual
  // step is two tests, answering() and the model's step. The usual step:
  // no link cut configured and nothing asked. Without a cut configured the
  // link is never down, so was_down_ is false already (only a cut sets it,
  // and set_link_down() without a cut clears it): the full step would only
  // store false there. Test: ScanSemantics.SimDeviceUsualStepEqualsFullLinkCutLogic.
  void step(TIME now, TIME dt) {
    if (down_at_.count() >= 0 || link_.maybe_queued()) [[unlikely]] {
      step_full(now, dt);
      return;
    }
    step_up(now, dt);
  }

  // Bind an FB's port straight to this device's buffers (tests).
  void bind(DevicePort& port) { port.bind(inputs_, outputs_, &link_); }

  // Fault switch (device params link_down_at / link_down_for, docs/config.md):
  // from `at` for `duration` the link is cut both ways, as a pulled cable
  // or a dead switch port: the model keeps the last outputs it received and
  // its answers are lost (the PLC keeps the last valid inputs and sees the
  // device Offline; records fail NotReachable). A negative `at` = never.
  void set_link_down(TIME at, TIME duration) {
    down_at_ = at;
    down_for_ = duration;
    if (at.count() < 0) was_down_ = false;  // what the next step() would make it
  }
  [[nodiscard]] bool link_down(TIME now) const {
    return down_at_.count() >= 0 && now >= down_at_ && now - down_at_ < down_for_;
  }

  DeviceModel& model() { return *model_; }
  DeviceLink& link() { return link_; }
  std::span<std::uint8_t> inputs() { return inputs_; }    // device -> PLC
  std::span<std::uint8_t> outputs() { return outputs_; }  // PLC -> device

 private:
  // The state set only when it changes (most steps: it does not): a set
  // is an exchange and a compare (DeviceLink::set_state counts a change),
  // a compare is a load. The device is its link's one writer while it steps
  // (the plugin's step, under its lock in real time), so a set of the
  // state the link has would store what is there and count nothing.
  void set_link_state(DeviceState s) {
    if (link_.live_state() != s) link_.set_state(s);
  }
  // The link is up: the model steps, answering or not.
  void step_up(TIME now, TIME dt) {
    if (model_->answering()) {
      model_->step(now, dt, from_plc_, to_plc_);
      set_link_state(DeviceState::Online);
    } else {
      // A silent device: the model still runs its physics, but its answer
      // is not delivered. The PLC keeps the last valid inputs (as a bus
      // master keeps the last valid frame) and sees the device Offline.
      model_->step(now, dt, from_plc_, silent_);
      set_link_state(DeviceState::Offline);
    }
  }
  void step_full(TIME now, TIME dt);  // step() with a cut configured or a record queued
  void serve_records(bool reachable);
  void step_cut(TIME now, TIME dt);  // step() while the link is down

  std::unique_ptr<DeviceModel> model_;
  std::vector<std::uint8_t> inputs_, outputs_, silent_sink_;
  // The three buffers as step() hands them to the model, taken once: they
  // never move or change size (DeviceLink makes the device neither
  // copyable nor movable).
  std::span<const std::uint8_t> from_plc_;
  std::span<std::uint8_t> to_plc_, silent_;
  std::vector<std::uint8_t> outputs_at_cut_;  // what the model keeps seeing while the link is down
  TIME down_at_{-1}, down_for_{0};
  bool was_down_ = false;
  DeviceLink link_;
};

}  // namespace plc::io

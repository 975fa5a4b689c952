// The fieldbus plugin interface.
//
// A plugin owns its bus timing and its threads. The scan never waits on a
// bus: at the start of a scan the owning task latches each device's inputs
// from the plugin's input staging, at the end it publishes the device's
// outputs into the output staging. Plugin threads never touch the live
// image. Acyclic requests reach the plugin through each device's DeviceLink.
//
// In virtual time the runtime calls step() once per base tick, before the
// tasks due at that tick, so devices advance in lockstep with the clock and a
// run is reproducible bit for bit. In real time the plugin runs its own
// thread(s) from start() to stop().
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "plc/io/device_link.hpp"
#include "plc/io/model_params.hpp"
#include "plc/types.hpp"

namespace plc::io {

enum class ClockMode : std::uint8_t { Virtual, RealTime };

struct DeviceSpec {
  std::string name;
  std::string model;   // device model / profile the plugin should use
  ModelParams params;  // the device's `params:` block
};

struct DeviceSizes {
  std::size_t input_bytes = 0;   // device -> PLC (%I)
  std::size_t output_bytes = 0;  // PLC -> device (%Q)
};

struct PluginStartError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Plugin {
 public:
  virtual ~Plugin() = default;

  // ---- set-up, before start (may throw ParamError) ----
  virtual void configure(const ModelParams& params) { params.reject_unknown(); }
  // Adds a device; its index is the number of devices added before it.
  virtual DeviceSizes add_device(const DeviceSpec& spec) = 0;

  // ---- life cycle ----
  virtual void start(ClockMode mode) = 0;  // may throw PluginStartError
  virtual void stop() = 0;
  // Virtual time only: advance every device by dt to `now`.
  virtual void step(TIME now, TIME dt) = 0;

  // ---- scan side: bounded time, no allocation, no exceptions ----
  virtual void latch_inputs(std::size_t device, std::span<std::uint8_t> dst) = 0;
  virtual void publish_outputs(std::size_t device, std::span<const std::uint8_t> src) = 0;
  virtual DeviceLink& link(std::size_t device) = 0;
  // A device's staging bytes, if the scan may copy them itself instead of
  // calling latch_inputs()/publish_outputs() (a virtual call and a memcpy
  // per device and scan, in virtual time a good part of a small device's
  // cost). Asked once, after start(); a plugin may answer only if, from
  // then on, those two calls would do nothing but copy from `in` and to
  // `out` (no lock, no bookkeeping) and the bytes never move: the sim
  // plugin in virtual time. Default: no.
  struct DirectIo {
    std::span<const std::uint8_t> in;  // what latch_inputs() copies from
    std::span<std::uint8_t> out;       // what publish_outputs() copies to
  };
  [[nodiscard]] virtual std::optional<DirectIo> direct_io(std::size_t /*device*/) {
    return std::nullopt;
  }

  // Human-readable state of a device for `stats` and logs.
  [[nodiscard]] virtual std::string diagnostics(std::size_t device) const;

  // ---- a plugin whose thread failed ----
  // Its thread (or, in virtual time, its step(), which the runtime guards)
  // ended by an exception: reported on stderr ("plcrun: <thread>: <what>",
  // plc/thread_guard.hpp), and from then on the plugin serves no device.
  // Its `devices` devices go to Fault, so that their FBs report an error
  // and put their outputs to the safe state at their next scan; the real
  // devices, no longer served, time out into theirs. Only the first call
  // counts. Never throws.
  void fail(std::string_view thread, std::string_view what, std::size_t devices) noexcept;
  [[nodiscard]] bool failed() const { return failed_.load(std::memory_order_acquire); }
  // Why ("" while it has not failed); summaries put it before diagnostics().
  [[nodiscard]] std::string failure() const;

 private:
  std::atomic<bool> failing_{false}, failed_{false};
  std::string failure_;  // written once, before failed_
};

using PluginFactory = std::function<std::unique_ptr<Plugin>()>;

class PluginRegistry {
 public:
  static PluginRegistry& instance();
  void add(const std::string& type, PluginFactory f);
  [[nodiscard]] const PluginFactory* find(const std::string& type) const;
  [[nodiscard]] std::vector<std::string> names() const;
  // While a cell library loads, its registrations are collected here
  // instead of taking effect (plc/cell_library.hpp): they count only once
  // its ABI version has been checked. nullptr: add() registers.
  void set_capture(std::map<std::string, PluginFactory>* c) { capture_ = c; }

 private:
  std::map<std::string, PluginFactory> factories_;
  std::map<std::string, PluginFactory>* capture_ = nullptr;
};

#define PLC_REGISTER_PLUGIN(type, Class)                                                       \
  namespace {                                                                                  \
  const bool plc_plugin_registered_##Class = [] {                                              \
    ::plc::io::PluginRegistry::instance().add(type, [] { return std::make_unique<Class>(); }); \
    return true;                                                                               \
  }();                                                                                         \
  }

}  // namespace plc::io

// The path tests' cell library (softplc_add_cell_library, as a cell project
// outside the tree builds one):
// - PathProbe counts its scans into a RETAIN variable, so a run shows that
//   the library was found and a warm start that the retain file was;
// - two plugins that refuse their configuration with exceptions other than
//   plc::io::ParamError (a plugin in a cell library may throw anything):
//   the cell is still refused with a config error at the entry.
#include <stdexcept>

#include "plc/io/plugin.hpp"
#include "plc/program.hpp"

using namespace plc;

class PathProbe : public ProgramBase<PathProbe> {
 public:
  DINT scans = 0;
  void cycle(const ScanContext&) override { ++scans; }
  PLC_REFLECT(scans)
  PLC_RETAIN(scans)
};
PLC_REGISTER_PROGRAM(PathProbe)

namespace {

class RefusingPlugin : public io::Plugin {
 public:
  void start(io::ClockMode) override {}
  void stop() override {}
  void step(TIME, TIME) override {}
  void latch_inputs(std::size_t, std::span<std::uint8_t>) override {}
  void publish_outputs(std::size_t, std::span<const std::uint8_t>) override {}
  io::DeviceLink& link(std::size_t) override { return link_; }

 private:
  io::DeviceLink link_;
};

class RefusesParams : public RefusingPlugin {
 public:
  void configure(const io::ModelParams&) override {
    throw std::runtime_error("this plugin refuses every configuration");
  }
  io::DeviceSizes add_device(const io::DeviceSpec&) override { return {}; }
};

class RefusesDevices : public RefusingPlugin {
 public:
  io::DeviceSizes add_device(const io::DeviceSpec&) override {
    throw std::invalid_argument("this plugin cannot connect any device");
  }
};

}  // namespace

PLC_REGISTER_PLUGIN("refuses_params", RefusesParams)
PLC_REGISTER_PLUGIN("refuses_devices", RefusesDevices)

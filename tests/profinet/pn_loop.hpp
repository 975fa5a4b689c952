// Lockstep harness for the controller tests: our Controller and one PnDevice
// per device (hosting the real device model) on an in-memory Ethernet hub
// and UDP network, advanced together in virtual time, 1 ms per step.
//
// One step: the controller sends what is due (the outputs the FBs wrote in
// the last scan), the devices take it, step their models and answer, and
// the controller reads their answers at once. FBs bound with bind() then
// see the device's inputs one scan after their outputs, as with the sim
// plugin's SimDevice (scan, then device step), so the scenarios of
// tests/drive and tests/safety run over PROFINET unchanged.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plc/io/device_port.hpp"
#include "plc/profinet/controller/controller.hpp"
#include "plc/profinet/description/builtin_descriptions.hpp"
#include "plc/profinet/device/pn_device.hpp"
#include "plc/profinet/link/memory_ethernet.hpp"
#include "plc/profinet/link/memory_udp.hpp"
#include "plc/scan_context.hpp"

namespace pntest {

using namespace std::chrono_literals;
using namespace plc::profinet;

inline Ipv4 ip_of(const char* s) { return *parse_ipv4(s); }

struct PnLoop {
  explicit PnLoop(ControllerConfig cfg = {}) : cfg_(cfg) {
    ctrl_eth = hub.port(Mac{0x02, 0, 0, 0, 0, 0x01});
    ctrl_udp = net.port(ip_of("192.168.0.1"), kPnioRpcPort);
    ctrl = std::make_unique<Controller>(cfg_, ctrl_eth.get(), ctrl_udp.get());
  }

  // A device of a built-in description ("hiwin_e1", "nord_profisafe") at
  // 192.168.0.(10 + index), named "<model>-<index>" with '_' as '-'.
  std::size_t add(const std::string& model, const plc::io::ModelParams& desc_params,
                  std::unique_ptr<plc::io::DeviceModel> m, ControllerDevice extra = {}) {
    const std::size_t i = devices.size();
    DeviceDescription desc = builtin_description(model, desc_params);
    std::string name = model + "-" + std::to_string(i);
    for (auto& c : name)
      if (c == '_') c = '-';
    desc.station_name = name;
    desc.ip = Ipv4{ip_of("192.168.0.10").host_order + static_cast<std::uint32_t>(i)};
    extra.name = name;
    extra.desc = desc;
    ctrl->add(extra);
    Dev d;
    d.model = m.get();
    d.eth = hub.port(Mac{0x02, 0, 0, 0, 0x10, static_cast<std::uint8_t>(0x10 + i)});
    PnDeviceConfig dc;
    dc.description = desc;
    MemoryUdp n = net;
    d.dev = std::make_unique<PnDevice>(dc, std::move(m), *d.eth,
                                       [n](Ipv4 ip) mutable { return n.port(ip, kPnioRpcPort); });
    devices.push_back(std::move(d));
    return i;
  }

  // One step of 1 ms (see the header comment).
  void step() {
    now += 1ms;
    hub.set_time(now);
    net.set_time(now);
    ctrl->poll(now);
    for (auto& d : devices)
      if (d.powered) d.dev->poll(now);
    ctrl->poll(now);
  }
  bool run_until(const std::function<bool()>& pred, int max_steps) {
    for (int i = 0; i < max_steps; ++i) {
      step();
      if (pred()) return true;
    }
    return false;
  }
  bool online(std::size_t i) const { return ctrl->state(i) == ArState::Online; }
  // FBs read and write the controller's staging buffers directly (as a
  // scan's latch/publish would copy them).
  void bind(plc::io::DevicePort& p, std::size_t i) {
    p.bind(ctrl->inputs(i), ctrl->outputs(i), &ctrl->link(i));
  }

  struct Dev {
    std::unique_ptr<EthernetPort> eth;
    std::unique_ptr<PnDevice> dev;
    plc::io::DeviceModel* model = nullptr;
    bool powered = true;  // false: polled no more (pulled plug / killed process)
  };
  ControllerConfig cfg_;
  MemoryEthernet hub;
  MemoryUdp net;
  std::unique_ptr<EthernetPort> ctrl_eth;
  std::unique_ptr<UdpPort> ctrl_udp;
  std::unique_ptr<Controller> ctrl;
  std::vector<Dev> devices;
  plc::TIME now{0};
};

}  // namespace pntest

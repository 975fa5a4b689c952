// dnslave: DeviceNet slaves in front of simulated devices, on a CAN bus
// (CAN over UDP or SocketCAN), in real time.
//
//   build/bin/dnslave slaves.yaml [--for 10s]
//
//   bus: udp:127.0.0.1:47800     # or socketcan:can0
//   hub: false                   # true: host the UDP hub of that bus here
//   pcap: bus.pcap               # optional capture of every frame seen
//   slaves:
//     - name: scale
//       model: pr5510            # a registered device model (as in a cell config)
//       params: {bus: devicenet} # the model's params
//       mac: 5
//       profile: pr1721_34       # identity + assemblies (slave_profiles.hpp)
//       serial: 1234             # identity overrides: vendor, device_type,
//                                # product_code, revision ("1.3"), serial, product_name
//       faults: {silent: false, size_error: 0, refuse_allocation: false}
//
// SIGUSR1 toggles "silent" on every slave (a pulled plug without killing the
// process); SIGTERM/SIGINT end it. Exit code 2 on a bad config (a relative
// pcap: file is taken from the config file's folder), 1 when it fails while
// it runs.
#include <poll.h>
#include <yaml-cpp/yaml.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "plc/can/bus.hpp"
#include "plc/can/fan_out.hpp"
#include "plc/can/pcap_writer.hpp"
#include "plc/can/udp_bus.hpp"
#include "plc/config_path.hpp"
#include "plc/devicenet/slave.hpp"
#include "plc/devicenet/slave_profiles.hpp"
#include "plc/fb/acdrive/assemblies.hpp"
#include "plc/iec_literal.hpp"
#include "plc/io/device_model.hpp"
#include "plc/io/sim_host.hpp"

namespace dn = plc::devicenet;
namespace io = plc::io;

namespace {

namespace sim_host = plc::io::sim_host;
using sim_host::ConfigError;
using sim_host::g_stop;
using sim_host::g_toggle_silent;
using sim_host::get_number;
using sim_host::mono_ns;
using sim_host::reject_unknown;

struct Hosted {
  std::string name;
  std::unique_ptr<plc::can::Bus> node;
  std::unique_ptr<dn::Slave> slave;
};

int run(int argc, char** argv) {
  const auto args = sim_host::parse_args("dnslave", argc, argv);
  if (!args) return 2;
  const std::string& file = args->config;
  const std::int64_t run_ns = args->run_ns;

  std::unique_ptr<plc::can::UdpHub> hub;
  std::unique_ptr<plc::can::Bus> bus;
  std::unique_ptr<plc::can::PcapWriter> pcap;
  std::unique_ptr<plc::can::FanOut> fan;
  std::vector<Hosted> slaves;
  const bool loaded = sim_host::load_config("dnslave", file, [&](const YAML::Node& root) {
    reject_unknown(root, {"bus", "hub", "pcap", "slaves"});
    const std::string spec = root["bus"] ? root["bus"].as<std::string>() : "udp:127.0.0.1:47800";
    if (root["hub"] && root["hub"].as<bool>()) {
      const std::string rest = spec.substr(4);
      const auto colon = rest.rfind(':');
      if (spec.rfind("udp:", 0) != 0 || colon == std::string::npos)
        throw ConfigError(root["hub"], "hub: true needs bus: udp:HOST:PORT");
      hub = std::make_unique<plc::can::UdpHub>(rest.substr(0, colon),
                                               std::stoi(rest.substr(colon + 1)));
    }
    bus = plc::can::open_bus(spec);
    fan = std::make_unique<plc::can::FanOut>(*bus);
    // A relative capture file is taken from the config file's folder.
    if (root["pcap"])
      pcap = std::make_unique<plc::can::PcapWriter>(
          plc::config_relative_path(file, root["pcap"].as<std::string>()));
    if (!root["slaves"] || !root["slaves"].IsSequence() || root["slaves"].size() == 0)
      throw ConfigError(root, "key 'slaves': a list of at least one slave");
    for (const YAML::Node& s : root["slaves"]) {
      reject_unknown(
          s, {"name", "model", "params", "mac", "profile", "vendor", "device_type", "product_code",
              "revision", "serial", "product_name", "faults", "input_assembly", "output_assembly"});
      if (!s["model"]) throw ConfigError(s, "key 'model' missing");
      if (!s["mac"]) throw ConfigError(s, "key 'mac' missing");
      const std::string model = s["model"].as<std::string>();
      dn::SlaveConfig cfg;
      if (s["profile"]) {
        const auto p = dn::slave_profile(s["profile"].as<std::string>());
        if (!p) throw ConfigError(s["profile"], "unknown profile (known: pr1721_34, dnet66z)");
        cfg = *p;
      }
      // The VF66B's assemblies follow its J-09/J-10 (§7.2): 21/71 for 0/1,
      // 100.. for the extended ones.
      if (model == "vf66b" && s["params"]) {
        if (s["params"]["j09"])
          cfg.output_assembly = plc::acdrive::output_instance(s["params"]["j09"].as<unsigned>());
        if (s["params"]["j10"])
          cfg.input_assembly = plc::acdrive::input_instance(s["params"]["j10"].as<unsigned>());
      }
      cfg.input_assembly = static_cast<std::uint8_t>(
          get_number<int>(s, "input_assembly", cfg.input_assembly, 1, 255));
      cfg.output_assembly = static_cast<std::uint8_t>(
          get_number<int>(s, "output_assembly", cfg.output_assembly, 1, 255));
      cfg.mac = static_cast<std::uint8_t>(get_number<int>(s, "mac", 0, 0, 63));
      auto& id = cfg.identity;
      id.vendor = static_cast<std::uint16_t>(get_number<int>(s, "vendor", id.vendor, 0, 65535));
      id.device_type =
          static_cast<std::uint16_t>(get_number<int>(s, "device_type", id.device_type, 0, 65535));
      id.product_code =
          static_cast<std::uint16_t>(get_number<int>(s, "product_code", id.product_code, 0, 65535));
      id.serial = static_cast<std::uint32_t>(
          get_number<long long>(s, "serial", 0x1000 + cfg.mac, 0, 0xFFFFFFFFLL));
      if (s["product_name"]) id.product_name = s["product_name"].as<std::string>();
      if (s["revision"]) {
        unsigned maj = 0, min = 0;
        if (std::sscanf(s["revision"].as<std::string>().c_str(), "%u.%u", &maj, &min) != 2 ||
            maj > 255 || min > 255)
          throw ConfigError(s["revision"], "revision: MAJOR.MINOR, each 0..255");
        id.major_rev = static_cast<std::uint8_t>(maj);
        id.minor_rev = static_cast<std::uint8_t>(min);
      }
      io::ModelParams params;
      params.set_folder(plc::config_folder(file));
      if (s["params"])
        for (const auto& kv : s["params"])
          params.set(kv.first.as<std::string>(), kv.second.as<std::string>());
      const io::DeviceModelFactory* f = io::DeviceModelRegistry::instance().find(model);
      if (!f) throw ConfigError(s["model"], "unknown device model '" + model + "'");
      std::unique_ptr<io::DeviceModel> m;
      try {
        m = (*f)(params);
      } catch (const io::ParamError& e) {
        throw ConfigError(s["params"] ? s["params"] : s,
                          "params: key '" + e.key + "': " + e.what());
      }
      Hosted h{s["name"] ? s["name"].as<std::string>() : model, fan->node(), nullptr};
      h.slave = std::make_unique<dn::Slave>(cfg, std::move(m), *h.node);
      if (const YAML::Node fl = s["faults"]) {
        reject_unknown(fl, {"silent", "size_error", "refuse_allocation"});
        h.slave->faults().silent = fl["silent"] && fl["silent"].as<bool>();
        h.slave->faults().size_error = get_number<int>(fl, "size_error", 0, -8, 8);
        h.slave->faults().refuse_allocation =
            fl["refuse_allocation"] && fl["refuse_allocation"].as<bool>();
      }
      for (const Hosted& o : slaves)
        if (o.slave->mac() == cfg.mac) throw ConfigError(s["mac"], "MAC ID used twice");
      slaves.push_back(std::move(h));
    }
  });
  if (!loaded) return 2;

  sim_host::install_signals();

  const std::int64_t t0 = mono_ns();
  int toggles_seen = 0;
  std::printf("dnslave: %zu slave(s) on the bus\n", slaves.size());
  std::fflush(stdout);
  while (!g_stop.load()) {
    const std::int64_t now = mono_ns() - t0;
    if (run_ns >= 0 && now >= run_ns) break;
    const int t = g_toggle_silent.load();
    for (; toggles_seen < t; ++toggles_seen)
      for (auto& h : slaves) h.slave->faults().silent = !h.slave->faults().silent;
    fan->pump([&](const plc::can::Frame& f) {
      if (pcap) pcap->write(f, now);
    });
    for (auto& h : slaves) h.slave->tick(plc::TIME(now));
    pollfd pfd{bus->fd(), POLLIN, 0};
    (void)poll(&pfd, 1, 1);
  }
  for (const auto& h : slaves)
    std::printf("dnslave: %s: %s\n", h.name.c_str(), h.slave->describe().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return sim_host::guarded_main("dnslave", run, argc, argv); }

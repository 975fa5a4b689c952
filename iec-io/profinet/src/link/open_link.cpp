#include "plc/profinet/link/open_link.hpp"

#include <map>
#include <mutex>

#include "plc/profinet/link/socket_udp_port.hpp"

namespace plc::profinet {

namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, MemoryEthernet> hubs;
  std::map<std::string, MemoryUdp> networks;
};

Registry& registry() {
  static Registry r;
  return r;
}

std::string memory_name(const std::string& spec) {
  const std::string name = spec.substr(4);
  if (name.empty()) throw LinkError("'" + spec + "': mem: needs a name (mem:NAME)");
  return name;
}

}  // namespace

bool is_memory_link(const std::string& spec) { return spec.rfind("mem:", 0) == 0; }

MemoryEthernet memory_ethernet(const std::string& name) {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  return r.hubs[name];
}

MemoryUdp memory_udp(const std::string& name) {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  return r.networks[name];
}

void set_memory_link_single_threaded(const std::string& spec, bool yes) {
  if (!is_memory_link(spec)) return;
  const std::string name = memory_name(spec);
  memory_ethernet(name).set_single_threaded(yes);
  memory_udp(name).set_single_threaded(yes);
}

void forget_memory_link(const std::string& name) {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  r.hubs.erase(name);
  r.networks.erase(name);
}

std::unique_ptr<EthernetPort> open_ethernet(const std::string& spec, Mac mac,
                                            RawEthernetOptions options) {
  if (spec.empty()) throw LinkError("no interface given (an interface name or mem:NAME)");
  if (is_memory_link(spec))
    return memory_ethernet(memory_name(spec)).port(mac, options.promiscuous);
  return std::make_unique<RawEthernetPort>(spec, options);
}

std::unique_ptr<UdpPort> open_udp(const std::string& spec, Ipv4 ip, std::uint16_t port) {
  if (is_memory_link(spec)) return memory_udp(memory_name(spec)).port(ip, port);
  return std::make_unique<SocketUdpPort>(ip, port);
}

}  // namespace plc::profinet

// Opening the transports from a config string, the form the `profinet`
// plugin's `interface:` key and pndevsim take:
//   "eth0"      a Linux interface: RawEthernetPort, and UDP sockets
//   "mem:NAME"  the in-memory hub and UDP network named NAME in this process
//               (created on first use; every opener of the same NAME is on
//               the same segment)
#pragma once

#include <memory>
#include <string>

#include "plc/profinet/link/memory_ethernet.hpp"
#include "plc/profinet/link/memory_udp.hpp"
#include "plc/profinet/link/raw_ethernet_port.hpp"

namespace plc::profinet {

[[nodiscard]] bool is_memory_link(const std::string& spec);

// Throws LinkError. `mac` is used by memory ports only (zero: the hub picks
// one); a real interface has its own. `options.promiscuous` holds for both:
// without it a memory port, as the raw socket, sees only the frames to its
// own MAC and to group addresses.
std::unique_ptr<EthernetPort> open_ethernet(const std::string& spec, Mac mac = {},
                                            RawEthernetOptions options = {});
// The UDP side that goes with `spec`: a SocketUdpPort bound to ip:port for
// an interface, a port of the named MemoryUdp network for "mem:NAME".
std::unique_ptr<UdpPort> open_udp(const std::string& spec, Ipv4 ip, std::uint16_t port);

// The named in-memory links (for fault hooks and virtual time in tests).
MemoryEthernet memory_ethernet(const std::string& name);
MemoryUdp memory_udp(const std::string& name);
// Declares the hub and network of "mem:NAME" used by one thread alone from
// now on, or no longer (MemoryEthernet::set_single_threaded); nothing for an
// interface.
void set_memory_link_single_threaded(const std::string& spec, bool yes);
// Forgets a name: later openers get a fresh hub and network (ports still
// open keep the old ones alive).
void forget_memory_link(const std::string& name);

}  // namespace plc::profinet

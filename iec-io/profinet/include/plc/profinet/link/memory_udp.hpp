// An in-memory UDP network for lockstep tests: port(ip, port) binds a
// UdpPort; a datagram sent to ip:port is, at once, in the queue of the port
// bound there (or to 0.0.0.0 and that port number); to nobody it is lost,
// as on a real network. Same fault hooks and threading (also
// set_single_threaded()) as MemoryEthernet, keyed by the sender's IP address.
#pragma once

#include <chrono>
#include <memory>

#include "plc/profinet/link/udp_port.hpp"

namespace plc::profinet {

class MemoryUdp {
 public:
  MemoryUdp();

  // Throws LinkError if ip:port is already bound.
  std::unique_ptr<UdpPort> port(Ipv4 ip, std::uint16_t port);

  void drop_next(Ipv4 from, int n);
  void delay_next(Ipv4 from, int n, std::chrono::nanoseconds d);
  void set_link_up(Ipv4 host, bool up);
  void set_single_threaded(bool yes);
  [[nodiscard]] bool single_threaded() const;
  void set_time(std::chrono::nanoseconds now);
  [[nodiscard]] std::chrono::nanoseconds time() const;
  [[nodiscard]] std::uint64_t datagrams_carried() const;

  struct Impl;

 private:
  std::shared_ptr<Impl> impl_;
};

}  // namespace plc::profinet

// A UDP socket bound to ip:port as a UdpPort (SO_REUSEADDR; waits with
// poll). 0.0.0.0 binds every address of the network namespace.
#pragma once

#include "plc/profinet/link/udp_port.hpp"

namespace plc::profinet {

class SocketUdpPort final : public UdpPort {
 public:
  // Throws LinkError (address not on this host, port in use, ...).
  SocketUdpPort(Ipv4 ip, std::uint16_t port);
  ~SocketUdpPort() override;
  SocketUdpPort(const SocketUdpPort&) = delete;
  SocketUdpPort& operator=(const SocketUdpPort&) = delete;

  [[nodiscard]] Ipv4 local_ip() const override { return ip_; }
  [[nodiscard]] std::uint16_t local_port() const override { return port_; }
  bool send_to(Ipv4 ip, std::uint16_t port, std::span<const std::uint8_t> data) override;
  std::size_t receive_from(std::span<std::uint8_t> buf, Ipv4& ip, std::uint16_t& port,
                           std::chrono::nanoseconds timeout) override;
  [[nodiscard]] int fd() const override { return fd_; }

 private:
  int fd_ = -1;
  Ipv4 ip_;
  std::uint16_t port_ = 0;
};

}  // namespace plc::profinet

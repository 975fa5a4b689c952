#include "plc/profinet/link/socket_udp_port.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "poll_wait.hpp"

namespace plc::profinet {

SocketUdpPort::SocketUdpPort(Ipv4 ip, std::uint16_t port) : ip_(ip), port_(port) {
  const std::string where = to_string(ip) + ":" + std::to_string(port);
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd_ < 0) throw LinkError("UDP " + where + ": socket: " + std::strerror(errno));
  const int one = 1;
  (void)::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(ip.host_order);
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    const int e = errno;
    ::close(fd_);
    fd_ = -1;
    throw LinkError("UDP " + where + ": cannot bind: " + std::strerror(e) +
                    (e == EADDRNOTAVAIL ? " (the address is not on an interface of this host or "
                                          "network namespace)"
                                        : ""));
  }
  if (port == 0) {
    socklen_t len = sizeof a;
    if (::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) == 0) port_ = ntohs(a.sin_port);
  }
}

SocketUdpPort::~SocketUdpPort() {
  if (fd_ >= 0) ::close(fd_);
}

bool SocketUdpPort::send_to(Ipv4 ip, std::uint16_t port, std::span<const std::uint8_t> data) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(ip.host_order);
  const ssize_t n = data.size() > kMaxDatagram
                        ? -1
                        : ::sendto(fd_, data.data(), data.size(), MSG_DONTWAIT,
                                   reinterpret_cast<sockaddr*>(&a), sizeof a);
  const bool ok = n == static_cast<ssize_t>(data.size());
  (ok ? counters_.sent : counters_.send_failed).fetch_add(1, std::memory_order_relaxed);
  return ok;
}

std::size_t SocketUdpPort::receive_from(std::span<std::uint8_t> buf, Ipv4& ip, std::uint16_t& port,
                                        std::chrono::nanoseconds timeout) {
  // Bounded: each pass either returns or drops one datagram.
  for (int pass = 0; pass < 64; ++pass) {
    if (!detail::wait_readable(fd_, pass == 0 ? timeout : timeout.zero())) return 0;
    sockaddr_in a{};
    socklen_t len = sizeof a;
    const ssize_t n = ::recvfrom(fd_, buf.data(), buf.size(), MSG_DONTWAIT | MSG_TRUNC,
                                 reinterpret_cast<sockaddr*>(&a), &len);
    if (n < 0) return 0;
    if (static_cast<std::size_t>(n) > buf.size()) {  // truncated: not delivered
      counters_.rx_dropped.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    ip = Ipv4{ntohl(a.sin_addr.s_addr)};
    port = ntohs(a.sin_port);
    counters_.received.fetch_add(1, std::memory_order_relaxed);
    return static_cast<std::size_t>(n);
  }
  return 0;
}

}  // namespace plc::profinet

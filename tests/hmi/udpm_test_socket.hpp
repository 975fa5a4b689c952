// A plain UDP socket on a multicast group, for the tests that put bytes on
// the wire that no LCM library would send (the hostile datagrams of issue
// 22), or that capture what a sender puts there as it is. Open it inside
// the test's network namespace (LoopbackNetns::in).
#pragma once

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "plc/hmi/transport_counters.hpp"
#include "udpm_test_datagrams.hpp"

namespace plctest::udpm {

class GroupSocket {
 public:
  // `listen`: also bound to the group and joined, to capture.
  GroupSocket(std::uint32_t group, std::uint16_t port, bool listen) {
    group_.sin_family = AF_INET;
    group_.sin_addr.s_addr = htonl(group);
    group_.sin_port = htons(port);
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    EXPECT_GE(fd_, 0);
    const int zero = 0, one = 1, big = 4 << 20;
    ::setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_TTL, &zero, sizeof zero);
    ::setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_LOOP, &one, sizeof one);
    if (!listen) return;
    ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &big, sizeof big);
    EXPECT_EQ(::bind(fd_, reinterpret_cast<const sockaddr*>(&group_), sizeof group_), 0);
    ip_mreq m{};
    m.imr_multiaddr = group_.sin_addr;
    EXPECT_EQ(::setsockopt(fd_, IPPROTO_IP, IP_ADD_MEMBERSHIP, &m, sizeof m), 0);
  }
  ~GroupSocket() { ::close(fd_); }
  GroupSocket(const GroupSocket&) = delete;
  GroupSocket& operator=(const GroupSocket&) = delete;

  void send(const Bytes& d) const {
    EXPECT_EQ(::sendto(fd_, d.data(), d.size(), 0, reinterpret_cast<const sockaddr*>(&group_),
                       sizeof group_),
              ssize_t(d.size()));
  }
  // The next datagram within 2 s, or nullopt.
  [[nodiscard]] std::optional<Bytes> next() const {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, 2000) != 1) return std::nullopt;
    Bytes b(plc::hmi::udpm::kMaxDatagram);
    const ssize_t n = ::recv(fd_, b.data(), b.size(), 0);
    if (n < 0) return std::nullopt;
    b.resize(std::size_t(n));
    return b;
  }

 private:
  int fd_ = -1;
  sockaddr_in group_{};
};

// The hostile datagrams of the test list aimed at `channel`, each
// with the reason our receiver counts it under.
inline std::vector<std::pair<Bytes, std::uint64_t plc::hmi::TransportCounters::*>> hostile_set(
    const std::string& channel) {
  using C = plc::hmi::TransportCounters;
  Bytes no_nul = lc02(3, channel, {});
  no_nul.pop_back();
  return {
      {wrapping_offset_fragment(channel), &C::bad_fragment},
      {Bytes{0x4C, 0x43, 0x30, 0x33, 0, 0, 0, 9, 0, 0, 0, 64}, &C::truncated},
      {lc03(4, 0xFFFFFFFFU, 0, 0, 2, channel, Bytes(32, 1)), &C::oversized},
      {lc03(5, 64, 0, 0, 0, channel, Bytes(32, 1)), &C::bad_fragment},
      {lc03(6, 64, 0, 7, 2, channel, Bytes(32, 1)), &C::bad_fragment},
      {no_nul, &C::channel_unterminated},
      {lc02(7, std::string(80, 'X'), {1}), &C::channel_too_long},
      {Bytes{'G', 'E', 'T', ' ', '/', ' ', 'H', 'T', 'T', 'P'}, &C::bad_magic},
  };
}

}  // namespace plctest::udpm

// The LCM urls the bridge and plcctl take, parsed here (not by liblcm) with
// an error that says what is wrong:
//   udpm://ADDR:PORT?ttl=N&recv_buf_size=BYTES   UDP multicast (udpm_transport.hpp)
//   udpm://                                      liblcm's default, 239.255.76.67:7667
//   memq://                                      in-process queue (tests)
// liblcm's syntax (lcm.c lcm_parse_url, lcm_udpm.c parse_mc_addr_and_port
// and new_argument), stricter: liblcm warns about an unknown option or a
// value that is not a number and carries on, and stores ttl=256 as 0; here
// each is an error. tcpq:// (lcm-server) is not offered: its receive path
// would be liblcm's own again.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace plc::hmi {

struct LcmUrl {
  enum class Kind { Udpm, Memq };
  Kind kind = Kind::Udpm;
  std::uint32_t group = 0xEFFF4C43;  // 239.255.76.67, host order
  std::uint16_t port = 7667;
  int ttl = 0;            // IP_MULTICAST_TTL: 0 keeps every datagram on this host
  int recv_buf_size = 0;  // SO_RCVBUF request; 0: the transport's default
};

// The url, or nullopt and `error` (the url named in it).
std::optional<LcmUrl> parse_lcm_url(const std::string& url, std::string& error);

}  // namespace plc::hmi

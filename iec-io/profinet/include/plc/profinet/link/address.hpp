// Link-layer and IP addresses of the PROFINET transports, and the one error
// type the real transports throw when they cannot be opened.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace plc::profinet {

// A MAC address, first byte first (as on the wire). wire/ethernet.hpp may
// declare the same alias.
using Mac = std::array<std::uint8_t, 6>;

std::string to_string(const Mac& m);             // "01:0e:cf:00:00:00"
std::optional<Mac> parse_mac(std::string_view);  // "01:0e:cf:00:00:00" or with '-'

struct Ipv4 {
  std::uint32_t host_order = 0;  // 192.168.0.1 = 0xC0A80001
  friend bool operator==(const Ipv4&, const Ipv4&) = default;
};

std::string to_string(Ipv4 ip);                    // "192.168.0.1"
std::optional<Ipv4> parse_ipv4(std::string_view);  // dotted quad only

// Opening a real transport failed: missing interface, missing CAP_NET_RAW,
// address in use... what() says which, and what to do about it.
struct LinkError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace plc::profinet

// Link-layer and IP addresses of the PROFINET transports, and the one error
// type the real transports throw when they cannot be opened.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace plc::profinet {

// A MAC address, first byte first (as on the wire). wire/ethernet.hpp may
// declare the same alias.
using Mac = std::array<std::uint8_t, 6>;

std::string to_string(const Mac& m);  // "01:0e:cf:00:00:00"

// Whether the 6 bytes at `a` and at `b` are the same MAC: two loads each,
// not a memcmp call (the in-memory hub and a device's output check compare
// one or more per frame).
inline bool same_mac(const std::uint8_t* a, const std::uint8_t* b) {
  std::uint32_t a4 = 0, b4 = 0;
  std::uint16_t a2 = 0, b2 = 0;
  std::memcpy(&a4, a, 4);
  std::memcpy(&a2, a + 4, 2);
  std::memcpy(&b4, b, 4);
  std::memcpy(&b2, b + 4, 2);
  return a4 == b4 && a2 == b2;
}
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

#include "plc/can/bus.hpp"

#include <charconv>

#include "plc/can/socketcan_bus.hpp"
#include "plc/can/udp_bus.hpp"

namespace plc::can {

const char* to_string(BusState s) {
  switch (s) {
    case BusState::ErrorActive:
      return "error-active";
    case BusState::ErrorPassive:
      return "error-passive";
    case BusState::BusOff:
      return "bus-off";
  }
  return "?";
}

std::unique_ptr<Bus> open_bus(const std::string& spec) {
  if (spec.rfind("socketcan:", 0) == 0) return std::make_unique<SocketCanBus>(spec.substr(10));
  if (spec.rfind("udp:", 0) == 0) {
    const std::string rest = spec.substr(4);
    const auto colon = rest.rfind(':');
    unsigned port = 0;
    if (colon == std::string::npos ||
        std::from_chars(rest.data() + colon + 1, rest.data() + rest.size(), port).ec !=
            std::errc() ||
        port == 0 || port > 65535)
      throw BusError("bus '" + spec + "': expected udp:HOST:PORT");
    return std::make_unique<UdpBus>(rest.substr(0, colon), static_cast<std::uint16_t>(port));
  }
  throw BusError("bus '" + spec + "': expected socketcan:IFNAME or udp:HOST:PORT");
}

}  // namespace plc::can

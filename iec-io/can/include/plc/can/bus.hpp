// A node's access to one CAN bus. Backends: SocketCAN (a real or virtual
// Linux interface), CAN over UDP (udp_bus.hpp) and an in-memory wire for
// lockstep tests (mem_bus.hpp).
//
// Every backend behaves like a SocketCAN socket with CAN_RAW_RECV_OWN_MSGS:
// a node receives every frame on the bus, its own transmissions included.
// send() and receive() never block; fd() (where there is one) can be given
// to poll() to wait for the next frame.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "plc/can/frame.hpp"

namespace plc::can {

enum class BusState : std::uint8_t { ErrorActive, ErrorPassive, BusOff };
const char* to_string(BusState s);

struct BusCounters {
  std::uint64_t tx = 0, rx = 0;
  std::uint64_t tx_dropped = 0;  // send() refused (queue full, socket error)
  std::uint64_t rx_bad = 0;      // malformed datagrams / frames, dropped
  std::uint64_t error_frames = 0;
};

class Bus {
 public:
  virtual ~Bus() = default;
  // Queue a frame for transmission; false when it could not be sent.
  virtual bool send(const Frame& f) = 0;
  // The next received frame, if any (error frames included, with kErr).
  virtual bool receive(Frame& f) = 0;
  // A descriptor that is readable when receive() may return a frame; -1 if
  // the backend has none (in-memory).
  [[nodiscard]] virtual int fd() const { return -1; }
  [[nodiscard]] virtual BusState state() const { return BusState::ErrorActive; }
  [[nodiscard]] virtual const BusCounters& counters() const = 0;
};

struct BusError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Opens a bus from its text form:
//   socketcan:IFNAME          e.g. socketcan:can0
//   udp:HOST:PORT             CAN over UDP through the hub at HOST:PORT
// Throws BusError with the reason.
std::unique_ptr<Bus> open_bus(const std::string& spec);

}  // namespace plc::can

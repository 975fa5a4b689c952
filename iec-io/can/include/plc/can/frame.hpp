// One classic CAN frame (11- or 29-bit identifier, 0..8 data bytes), the
// unit every CAN backend (SocketCAN, CAN over UDP, in-memory) carries.
#pragma once

#include <array>
#include <cstdint>

namespace plc::can {

struct Frame {
  // Identifier flags as in SocketCAN's can_id (linux/can.h), so a frame
  // crosses SocketCAN, the UDP datagram format and pcap unchanged.
  static constexpr std::uint32_t kEff = 0x80000000u;  // 29-bit identifier
  static constexpr std::uint32_t kRtr = 0x40000000u;  // remote request
  static constexpr std::uint32_t kErr = 0x20000000u;  // error frame (SocketCAN)
  static constexpr std::uint32_t kSffMask = 0x7FFu;
  static constexpr std::uint32_t kEffMask = 0x1FFFFFFFu;

  std::uint32_t id = 0;  // identifier | flags
  std::uint8_t len = 0;  // 0..8
  std::array<std::uint8_t, 8> data{};

  [[nodiscard]] bool extended() const { return (id & kEff) != 0; }
  [[nodiscard]] bool remote() const { return (id & kRtr) != 0; }
  [[nodiscard]] bool error() const { return (id & kErr) != 0; }
  // The 11-bit identifier of a standard data frame.
  [[nodiscard]] std::uint16_t std_id() const { return static_cast<std::uint16_t>(id & kSffMask); }
};

}  // namespace plc::can

// DeviceNet 11-bit CAN identifiers (toyo-vf66-devicenet.md §1.4, table of
// message groups; fieldbus-masters.md §2):
//   Group 1: (message id << 6) | MAC          0x000..0x3FF
//   Group 2: 0x400 | (MAC << 3) | message id  0x400..0x5FF
//   Group 3: 0x600 | (message id << 6) | MAC  0x600..0x7BF
//   Group 4: 0x7C0..0x7EF; 0x7F0..0x7FF invalid
#pragma once

#include <cstdint>
#include <optional>

namespace plc::devicenet {

inline constexpr std::uint8_t kMaxMac = 63;

// Group 1 message ids (slave -> master).
inline constexpr std::uint8_t kG1MulticastPollResponse = 0xC;
inline constexpr std::uint8_t kG1ChangeOfState = 0xD;
inline constexpr std::uint8_t kG1BitStrobeResponse = 0xE;
inline constexpr std::uint8_t kG1PollResponse = 0xF;
// Group 2 message ids.
inline constexpr std::uint8_t kG2BitStrobe = 0;
inline constexpr std::uint8_t kG2MulticastPoll = 1;
inline constexpr std::uint8_t kG2CosAck = 2;
inline constexpr std::uint8_t kG2ExplicitResponse = 3;
inline constexpr std::uint8_t kG2ExplicitRequest = 4;
inline constexpr std::uint8_t kG2Poll = 5;
inline constexpr std::uint8_t kG2Unconnected = 6;
inline constexpr std::uint8_t kG2DupMac = 7;

[[nodiscard]] constexpr std::uint16_t group1_id(std::uint8_t msg, std::uint8_t mac) {
  return static_cast<std::uint16_t>(((msg & 0xF) << 6) | (mac & 0x3F));
}
[[nodiscard]] constexpr std::uint16_t group2_id(std::uint8_t mac, std::uint8_t msg) {
  return static_cast<std::uint16_t>(0x400 | ((mac & 0x3F) << 3) | (msg & 0x7));
}

struct Identifier {
  std::uint8_t group = 0;  // 1..4
  std::uint8_t msg = 0;
  std::uint8_t mac = 0;  // 0 for group 4
};

// Splits an identifier; nullopt for 0x7F0..0x7FF (invalid) or above 11 bits.
[[nodiscard]] constexpr std::optional<Identifier> decode_id(std::uint32_t id) {
  if (id > 0x7FF || id >= 0x7F0) return std::nullopt;
  if (id < 0x400)
    return Identifier{1, static_cast<std::uint8_t>(id >> 6), static_cast<std::uint8_t>(id & 0x3F)};
  if (id < 0x600)
    return Identifier{2, static_cast<std::uint8_t>(id & 0x7),
                      static_cast<std::uint8_t>((id >> 3) & 0x3F)};
  if (id < 0x7C0)
    return Identifier{3, static_cast<std::uint8_t>((id >> 6) & 0x7),
                      static_cast<std::uint8_t>(id & 0x3F)};
  return Identifier{4, static_cast<std::uint8_t>(id & 0x3F), 0};
}

}  // namespace plc::devicenet

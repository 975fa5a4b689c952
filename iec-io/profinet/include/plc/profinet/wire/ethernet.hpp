// Ethernet II framing of PROFINET (IEC 61158-6-10 §4.2 / IEEE 802.3):
//   dst MAC (6) | src MAC (6) | [0x8100 | TCI (2)] | EtherType 0x8892 | FrameID (2) | PDU
// Frames are sent without FCS and padded to the 60-byte minimum. Receivers
// accept the PROFINET EtherType with and without one IEEE 802.1Q tag
// (devices may send priority-tagged frames, VLAN 0 priority 6).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>

#include "plc/profinet/wire/codec.hpp"

namespace plc::profinet {

using Mac = std::array<std::uint8_t, 6>;

inline constexpr std::uint16_t kEtherTypeProfinet = 0x8892;
inline constexpr std::uint16_t kEtherTypeVlan = 0x8100;
inline constexpr std::uint16_t kEtherTypeIpv4 = 0x0800;
inline constexpr std::size_t kEthernetHeaderLength = 14;
inline constexpr std::size_t kVlanTagLength = 4;
inline constexpr std::size_t kMinFrameLength = 60;    // without FCS
inline constexpr std::size_t kMaxFrameLength = 1518;  // with one VLAN tag, without FCS
// Priority 6 (the RT_CLASS_1 default), VLAN 0: TCI 0xC000.
inline constexpr std::uint16_t kVlanTciPriority6 = 0xC000;

// DCP Identify multicast (IEC 61158-6-10 Table "Multicast MAC addresses").
inline constexpr Mac kDcpIdentifyMulticast{0x01, 0x0E, 0xCF, 0x00, 0x00, 0x00};
// DCP Hello multicast.
inline constexpr Mac kDcpHelloMulticast{0x01, 0x0E, 0xCF, 0x00, 0x00, 0x01};

// FrameIDs (IEC 61158-6-10 Table "FrameID range").
namespace frame_id {
inline constexpr std::uint16_t kRtClass3First = 0x0100;  // RT_CLASS_3 (and streams)
inline constexpr std::uint16_t kRtClass3Last = 0x7FFF;
inline constexpr std::uint16_t kRtClass2First = 0x8000;  // RT_CLASS_2 unicast
inline constexpr std::uint16_t kRtClass2Last = 0xBBFF;
inline constexpr std::uint16_t kRtClass1First = 0xC000;  // RT_CLASS_1 unicast
inline constexpr std::uint16_t kRtClass1Last = 0xF7FF;
inline constexpr std::uint16_t kCyclicLast =
    0xFBFF;  // end of the cyclic ranges (RT_CLASS_1 multicast)
inline constexpr std::uint16_t kAlarmHigh = 0xFC01;
inline constexpr std::uint16_t kAlarmLow = 0xFE01;
inline constexpr std::uint16_t kDcpHello = 0xFEFC;
inline constexpr std::uint16_t kDcpGetSet = 0xFEFD;
inline constexpr std::uint16_t kDcpIdentifyRequest = 0xFEFE;
inline constexpr std::uint16_t kDcpIdentifyResponse = 0xFEFF;
}  // namespace frame_id
[[nodiscard]] constexpr bool is_rt_class1(std::uint16_t id) {
  return id >= frame_id::kRtClass1First && id <= frame_id::kRtClass1Last;
}
// Any cyclic RT FrameID (RT_CLASS_3 .. RT_CLASS_1 multicast): the frame
// layout is the same in every range, only the schedule differs.
[[nodiscard]] constexpr bool is_cyclic(std::uint16_t id) {
  return id >= frame_id::kRtClass3First && id <= frame_id::kCyclicLast;
}
[[nodiscard]] constexpr bool is_dcp(std::uint16_t id) {
  return id >= frame_id::kDcpHello && id <= frame_id::kDcpIdentifyResponse;
}
[[nodiscard]] constexpr bool is_alarm(std::uint16_t id) {
  return id == frame_id::kAlarmHigh || id == frame_id::kAlarmLow;
}

// A received PROFINET frame, as views into the caller's buffer.
struct PnFrameView {
  Mac dst{};
  Mac src{};
  std::optional<std::uint16_t> vlan_tci;  // set when the frame carried a 802.1Q tag
  std::uint16_t frame_id = 0;
  std::span<const std::uint8_t> pdu;  // after the FrameID, up to the frame's end (incl. padding)
};

// Parses the Ethernet header (tagged or not) and the FrameID. Refuses
// other EtherTypes and frames shorter than header + FrameID. Every received
// frame goes through here: read in place, no byte-reader bookkeeping, and
// inline (the receivers use few of the fields).
inline WireStatus decode_pn_frame(std::span<const std::uint8_t> frame, PnFrameView& out) {
  const auto be16 = [](const std::uint8_t* p) {
    return static_cast<std::uint16_t>(p[0] << 8 | p[1]);
  };
  out.vlan_tci.reset();
  if (frame.size() < kEthernetHeaderLength + 2)
    return wire_fail(WireError::Truncated, "frame shorter than its header");
  const std::uint8_t* p = frame.data();
  std::uint16_t type = be16(p + 12);
  std::size_t at = kEthernetHeaderLength;
  if (type == kEtherTypeVlan) {
    if (frame.size() < kEthernetHeaderLength + kVlanTagLength + 2)
      return wire_fail(WireError::Truncated, "frame shorter than its header");
    out.vlan_tci = be16(p + 14);
    type = be16(p + 16);
    at += kVlanTagLength;
  }
  out.frame_id = be16(p + at);
  if (type != kEtherTypeProfinet) return wire_fail(WireError::BadEtherType, "not EtherType 0x8892");
  std::memcpy(out.dst.data(), p, 6);  // two fixed-size moves, not byte loops
  std::memcpy(out.src.data(), p + 6, 6);
  out.pdu = frame.subspan(at + 2);
  return kWireOk;
}

// Writes dst, src, the optional tag, EtherType 0x8892 and the FrameID;
// returns the header length (14/18 + 2), 0 if `out` is too small.
std::size_t encode_pn_header(std::span<std::uint8_t> out, const Mac& dst, const Mac& src,
                             std::uint16_t frame_id, std::optional<std::uint16_t> vlan_tci = {});

// Pads a frame of `length` bytes with zeros to the 60-byte minimum; returns
// the new length (0 if `out` is too small for it).
std::size_t pad_frame(std::span<std::uint8_t> out, std::size_t length);

// The 0x8892 frame as a vector (acyclic PDUs): header + pdu, padded.
std::vector<std::uint8_t> build_pn_frame(const Mac& dst, const Mac& src, std::uint16_t frame_id,
                                         std::span<const std::uint8_t> pdu,
                                         std::optional<std::uint16_t> vlan_tci = {});

}  // namespace plc::profinet

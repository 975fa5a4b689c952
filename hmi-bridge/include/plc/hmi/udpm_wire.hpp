// LCM's UDP multicast wire format ("udpm"), byte for byte as liblcm 1.3.1
// (Debian 12) writes it, so that lcm-logger, lcm-spy, lcm-logplayer and any
// other LCM program on the group talk with the bridge and plcctl. Source:
// lcm-proj/lcm v1.3.1, lcm/udpm_util.h (magics, sizes, header structs) and
// lcm/lcm_udpm.c (lcm_udpm_publish). All integers big-endian.
//
//   short message, one datagram ("LC02"):
//     magic u32 0x4c433032, seqno u32, channel, NUL, payload
//   fragment of a longer message ("LC03"):
//     magic u32 0x4c433033, seqno u32, msg_size u32 (the whole payload),
//     fragment_offset u32 (of this piece in the payload), fragment_no u16,
//     n_fragments u16; fragment 0 only: channel, NUL; then the piece
//
// A sender counts its messages (seqno, +1 per message, wrapping); every
// fragment of a message carries the message's seqno. liblcm sends a message
// short when channel + NUL + payload fit in 65499 bytes, else in fragments
// of 65487 bytes each (channel and NUL counted in fragment 0), at most 65535.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <utility>

namespace plc::hmi::udpm {

inline constexpr std::uint32_t kMagicShort = 0x4c433032;     // "LC02", udpm_util.h:36
inline constexpr std::uint32_t kMagicFragment = 0x4c433033;  // "LC03", udpm_util.h:37
inline constexpr std::size_t kShortHeaderSize = 8;           // lcm2_header_short_t
inline constexpr std::size_t kFragmentHeaderSize = 20;       // lcm2_header_long_t
inline constexpr std::size_t kMaxChannelLength = 63;  // LCM_MAX_CHANNEL_NAME_LENGTH, lcm.h:14
// channel + NUL + payload of a short message (LCM_SHORT_MESSAGE_MAX_SIZE,
// udpm_util.h:43): 8 + 65499 = 65507, the largest UDP payload over IPv4.
inline constexpr std::size_t kShortMessageMaxSize = 65499;
// Bytes after the header of one fragment (LCM_FRAGMENT_MAX_PAYLOAD, udpm_util.h:44).
inline constexpr std::size_t kFragmentMaxPayload = 65487;
inline constexpr std::size_t kMaxFragments = 65535;  // n_fragments is a u16 (lcm_udpm.c:663)
// A receive buffer that holds any UDP datagram over IPv4.
inline constexpr std::size_t kMaxDatagram = 65536;

inline void put_u16(std::uint8_t* p, std::uint16_t v) {
  p[0] = std::uint8_t(v >> 8);
  p[1] = std::uint8_t(v);
}
inline void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) p[k] = std::uint8_t(v >> (24 - 8 * k));
}
inline std::uint16_t get_u16(const std::uint8_t* p) { return std::uint16_t(p[0] << 8 | p[1]); }
inline std::uint32_t get_u32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 |
         std::uint32_t(p[3]);
}

// One datagram to send: a header (with the channel, where it goes) written
// here, then a piece of the caller's payload (sent with sendmsg's iovecs,
// never copied).
struct Datagram {
  std::array<std::uint8_t, kFragmentHeaderSize + kMaxChannelLength + 1> head{};
  std::size_t head_size = 0;
  std::span<const std::uint8_t> body;
  [[nodiscard]] std::size_t size() const { return head_size + body.size(); }
};

// How many datagrams liblcm sends for this message: 1 (short), the number
// of fragments, or 0 when it cannot be sent (channel longer than 63, more
// than 65535 fragments).
std::size_t datagram_count(std::string_view channel, std::size_t payload_size);

// Calls send(const Datagram&) for each datagram of one message, in order,
// exactly as lcm_udpm_publish does; stops early when send returns false.
// Returns the datagrams sent (0: the message cannot be sent).
template <class Send>
std::size_t for_each_datagram(std::string_view channel, std::span<const std::uint8_t> payload,
                              std::uint32_t seqno, Send send) {
  const std::size_t n = datagram_count(channel, payload.size());
  if (n == 0) return 0;
  Datagram d;
  put_u32(d.head.data() + 4, seqno);
  if (n == 1) {
    put_u32(d.head.data(), kMagicShort);
    channel.copy(reinterpret_cast<char*>(d.head.data()) + kShortHeaderSize, channel.size());
    d.head[kShortHeaderSize + channel.size()] = 0;
    d.head_size = kShortHeaderSize + channel.size() + 1;
    d.body = payload;
    return send(std::as_const(d)) ? 1 : 0;
  }
  put_u32(d.head.data(), kMagicFragment);
  put_u32(d.head.data() + 8, std::uint32_t(payload.size()));
  put_u16(d.head.data() + 18, std::uint16_t(n));
  std::size_t offset = 0;
  for (std::size_t k = 0; k < n; ++k) {
    put_u32(d.head.data() + 12, std::uint32_t(offset));
    put_u16(d.head.data() + 16, std::uint16_t(k));
    std::size_t room = kFragmentMaxPayload;
    d.head_size = kFragmentHeaderSize;
    if (k == 0) {  // the channel travels in fragment 0 only, inside its 65487 bytes
      channel.copy(reinterpret_cast<char*>(d.head.data()) + kFragmentHeaderSize, channel.size());
      d.head[kFragmentHeaderSize + channel.size()] = 0;
      d.head_size += channel.size() + 1;
      room -= channel.size() + 1;
    }
    const std::size_t piece = std::min(room, payload.size() - offset);
    d.body = payload.subspan(offset, piece);
    if (!send(std::as_const(d))) return k;
    offset += piece;
  }
  return n;
}

}  // namespace plc::hmi::udpm

// Datagrams of LCM's udpm format written field by field (not through our
// encoder), for the codec's known answers and the hostile-datagram tests:
// liblcm 1.3.1, lcm/udpm_util.h lcm2_header_short_t / lcm2_header_long_t,
// all big-endian.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "plc/hmi/udpm_wire.hpp"

namespace plctest::udpm {

using Bytes = std::vector<std::uint8_t>;

inline void u16(Bytes& b, std::uint16_t v) {
  b.push_back(std::uint8_t(v >> 8));
  b.push_back(std::uint8_t(v));
}
inline void u32(Bytes& b, std::uint32_t v) {
  for (int k = 3; k >= 0; --k) b.push_back(std::uint8_t(v >> (8 * k)));
}
inline void text(Bytes& b, std::string_view s) { b.insert(b.end(), s.begin(), s.end()); }

// "LC02", seqno, channel, NUL, payload.
inline Bytes lc02(std::uint32_t seqno, std::string_view channel, const Bytes& payload) {
  Bytes b;
  u32(b, plc::hmi::udpm::kMagicShort);
  u32(b, seqno);
  text(b, channel);
  b.push_back(0);
  b.insert(b.end(), payload.begin(), payload.end());
  return b;
}

// "LC03", seqno, msg_size, fragment_offset, fragment_no, n_fragments, then
// (fragment 0) channel and NUL, then the piece.
inline Bytes lc03(std::uint32_t seqno, std::uint32_t msg_size, std::uint32_t offset,
                  std::uint16_t no, std::uint16_t n, std::string_view channel, const Bytes& piece) {
  Bytes b;
  u32(b, plc::hmi::udpm::kMagicFragment);
  u32(b, seqno);
  u32(b, msg_size);
  u32(b, offset);
  u16(b, no);
  u16(b, n);
  if (no == 0) {
    text(b, channel);
    b.push_back(0);
  }
  b.insert(b.end(), piece.begin(), piece.end());
  return b;
}

// The datagram of issue 22: fragment 0 of a 64-byte message on `channel`
// whose 32-byte piece claims offset 0xFFFFFFF0. liblcm 1.3.1 checks
// fragment_offset + frag_size > data_size in 32 bits (0x10: passes) and
// copies the piece 4 GiB past its 64-byte buffer (lcm_udpm.c:316-324).
// 60 bytes on PLC_CMD.
inline Bytes wrapping_offset_fragment(std::string_view channel = "PLC_CMD",
                                      std::uint32_t seqno = 1) {
  return lc03(seqno, 64, 0xFFFFFFF0U, 0, 2, channel, Bytes(32, 0x41));
}

// `n` bytes of a fixed pattern (the payload of the valid messages).
inline Bytes pattern(std::size_t n, std::uint8_t seed = 0) {
  Bytes b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = std::uint8_t(i * 31 + seed + (i >> 8));
  return b;
}

// Our encoder's datagrams of one message, each as one byte string.
inline std::vector<Bytes> encode(std::string_view channel, const Bytes& payload,
                                 std::uint32_t seqno) {
  std::vector<Bytes> out;
  plc::hmi::udpm::for_each_datagram(channel, payload, seqno,
                                    [&](const plc::hmi::udpm::Datagram& d) {
                                      Bytes b(d.head.begin(), d.head.begin() + long(d.head_size));
                                      b.insert(b.end(), d.body.begin(), d.body.end());
                                      out.push_back(std::move(b));
                                      return true;
                                    });
  return out;
}

}  // namespace plctest::udpm

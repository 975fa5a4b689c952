#include "plc/can/udp_datagram.hpp"

namespace plc::can::udp {

std::size_t encode(std::uint8_t seq, std::span<const Frame> frames, std::span<std::uint8_t> out) {
  if (frames.size() > kMaxFramesPerDatagram || out.size() < kHeaderSize) return 0;
  out[0] = kVersion;
  out[1] = kOpData;
  out[2] = seq;
  out[3] = static_cast<std::uint8_t>(frames.size() >> 8);
  out[4] = static_cast<std::uint8_t>(frames.size());
  std::size_t n = kHeaderSize;
  for (const Frame& f : frames) {
    if (f.len > 8 || out.size() < n + 5 + f.len) return 0;
    out[n++] = static_cast<std::uint8_t>(f.id >> 24);
    out[n++] = static_cast<std::uint8_t>(f.id >> 16);
    out[n++] = static_cast<std::uint8_t>(f.id >> 8);
    out[n++] = static_cast<std::uint8_t>(f.id);
    out[n++] = f.len;
    for (std::size_t i = 0; i < f.len; ++i) out[n++] = f.data[i];
  }
  return n;
}

int decode(std::span<const std::uint8_t> d, std::span<Frame> out) {
  if (d.size() < kHeaderSize || d[0] != kVersion || d[1] != kOpData) return -1;
  const std::size_t count = (std::size_t(d[3]) << 8) | d[4];
  if (count > out.size()) return -1;
  std::size_t pos = kHeaderSize;
  for (std::size_t k = 0; k < count; ++k) {
    if (d.size() < pos + 5) return -1;
    Frame f;
    f.id = (std::uint32_t(d[pos]) << 24) | (std::uint32_t(d[pos + 1]) << 16) |
           (std::uint32_t(d[pos + 2]) << 8) | d[pos + 3];
    f.len = d[pos + 4];
    pos += 5;
    // cannelloni marks CAN FD frames with bit 7 of the length: classic only.
    if (f.len > 8 || d.size() < pos + f.len) return -1;
    if (!f.extended() && (f.id & ~(Frame::kRtr | Frame::kErr)) > Frame::kSffMask) return -1;
    for (std::size_t i = 0; i < f.len; ++i) f.data[i] = d[pos + i];
    pos += f.len;
    out[k] = f;
  }
  if (pos != d.size()) return -1;  // trailing bytes: not a datagram we understand
  return static_cast<int>(count);
}

}  // namespace plc::can::udp

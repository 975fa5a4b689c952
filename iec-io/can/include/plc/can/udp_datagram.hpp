// The CAN-over-UDP datagram: cannelloni's UDP format version 2, so our bus
// can talk to a cannelloni gateway (also on microcontrollers with lwIP) as
// well as to itself. All fields big-endian:
//
//   byte 0     version = 2
//   byte 1     op code = 0 (DATA)
//   byte 2     sequence number (mod 256, per sender)
//   bytes 3-4  frame count N (0 = a keep-alive: "I am on this bus")
//   N times:   can_id (4 bytes, SocketCAN layout with the EFF/RTR/ERR
//              flags in bits 31..29), length (1 byte, 0..8), data (length
//              bytes)
//
// A datagram that breaks any rule (version, op code, a length above 8, a
// count that does not match the bytes) is rejected whole: counted and
// dropped by the receiver, never partly delivered.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "plc/can/frame.hpp"

namespace plc::can::udp {

inline constexpr std::uint8_t kVersion = 2;
inline constexpr std::uint8_t kOpData = 0;
inline constexpr std::size_t kHeaderSize = 5;
inline constexpr std::size_t kMaxFrameSize = 4 + 1 + 8;
inline constexpr std::size_t kMaxFramesPerDatagram = 64;
inline constexpr std::size_t kMaxDatagram = kHeaderSize + kMaxFramesPerDatagram * kMaxFrameSize;

// Writes a datagram with `frames` into `out`; returns its length (0 if it
// does not fit or a frame is invalid).
std::size_t encode(std::uint8_t seq, std::span<const Frame> frames, std::span<std::uint8_t> out);

// Decodes a datagram into `out` (at most out.size() frames). Returns the
// number of frames, or -1 when the datagram is malformed.
int decode(std::span<const std::uint8_t> datagram, std::span<Frame> out);

}  // namespace plc::can::udp

// Explicit message frames of the Predefined Master/Slave Connection Set,
// 8/8 body format (toyo-vf66-devicenet.md §1.4 [std]):
//   byte 0  header: bit7 Frag, bit6 XID, bits5..0 MAC ID (the master's in
//           both directions of a Group 2 connection)
//   unfragmented: byte 1 service (bit7 = response), then the body
//   fragmented:   byte 1 fragmentation byte (type bits 7..6: 0 first,
//           1 middle, 2 last, 3 ack; count bits 5..0), then up to 6 bytes
//           of the message (service, body); an ack carries one status byte
//           (0 success, 1 too much data).
// A message is the service byte plus its body (class, instance[, attribute],
// data for requests; data for responses; general + additional status for
// the Error Response 0x94).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "plc/can/frame.hpp"

namespace plc::devicenet {

enum class FragType : std::uint8_t { First = 0, Middle = 1, Last = 2, Ack = 3 };

inline constexpr std::uint8_t kFragBit = 0x80;
inline constexpr std::uint8_t kXidBit = 0x40;
inline constexpr std::uint8_t kResponseBit = 0x80;
inline constexpr std::uint8_t kAckSuccess = 0;
inline constexpr std::uint8_t kAckTooMuchData = 1;
// The largest explicit message we assemble: service + 2 path bytes + the
// record path's 240 bytes (record_request.hpp) + attribute, with room.
inline constexpr std::size_t kMaxExplicitMessage = 256;
// Data bytes of one explicit fragment (8 - header - fragmentation byte).
inline constexpr std::size_t kExplicitFragmentData = 6;
// Data bytes of one I/O fragment (8 - fragmentation byte).
inline constexpr std::size_t kIoFragmentData = 7;

[[nodiscard]] constexpr std::uint8_t frag_byte(FragType t, std::uint8_t count) {
  return static_cast<std::uint8_t>((static_cast<std::uint8_t>(t) << 6) | (count & 0x3F));
}
[[nodiscard]] constexpr FragType frag_type(std::uint8_t b) { return FragType(b >> 6); }
[[nodiscard]] constexpr std::uint8_t frag_count(std::uint8_t b) { return b & 0x3F; }

// The frames of one explicit message (at most 64 fragments: 6 * 64 = 384
// bytes > kMaxExplicitMessage). Fragment k (k >= 0) is sent only after the
// ack of fragment k-1.
struct ExplicitFrames {
  std::array<can::Frame, 64> frames{};
  std::size_t count = 0;
};
// Builds the frames for message `msg` on identifier `id`; false when the
// message is empty or too long.
bool build_explicit(std::uint16_t id, std::uint8_t header_mac, bool xid,
                    std::span<const std::uint8_t> msg, ExplicitFrames& out);

// The ack frame for a received fragment.
can::Frame explicit_ack(std::uint16_t id, std::uint8_t header_mac, bool xid, std::uint8_t count,
                        std::uint8_t status);

// Reassembles one direction of an explicit connection.
class ExplicitReassembler {
 public:
  enum class Result : std::uint8_t {
    Ignored,       // not an explicit frame we take (too short)
    Message,       // a complete unfragmented message is in message()
    FragmentAck,   // a fragment was taken: send an ack for ack_count()
    LastFragment,  // the last fragment: send an ack, and message() is complete
    AckReceived,   // the peer acknowledged our fragment ack_count()
    Bad,           // malformed or out of sequence: dropped, state reset
  };
  Result take(const can::Frame& f);
  [[nodiscard]] std::span<const std::uint8_t> message() const { return {buf_.data(), len_}; }
  [[nodiscard]] std::uint8_t header_mac() const { return mac_; }
  [[nodiscard]] bool xid() const { return xid_; }
  [[nodiscard]] std::uint8_t ack_count() const { return ack_count_; }
  [[nodiscard]] std::uint8_t ack_status() const { return ack_status_; }
  void reset() {
    len_ = 0;
    in_progress_ = false;
  }

 private:
  std::array<std::uint8_t, kMaxExplicitMessage> buf_{};
  std::size_t len_ = 0;
  bool in_progress_ = false;
  std::uint8_t next_count_ = 0;
  std::uint8_t mac_ = 0;
  bool xid_ = false;
  std::uint8_t ack_count_ = 0;
  std::uint8_t ack_status_ = 0;
};

// I/O data: one frame up to 8 bytes, else fragments of 7 data bytes after
// a fragmentation byte, no acks (§1.4 [std]).
struct IoFrames {
  std::array<can::Frame, 64> frames{};
  std::size_t count = 0;
};
bool build_io(std::uint16_t id, std::span<const std::uint8_t> data, IoFrames& out);

// Reassembles I/O data of a known expected size (> 8 bytes: fragmented).
class IoReassembler {
 public:
  enum class Result : std::uint8_t { Partial, Complete, Bad };
  explicit IoReassembler(std::size_t expected = 0) : expected_(expected) {}
  void set_expected(std::size_t n) {
    expected_ = n;
    reset();
  }
  // Complete: data() holds the message (its length may differ from the
  // expected size when the producer sends another size; the caller checks).
  Result take(const can::Frame& f);
  [[nodiscard]] std::span<const std::uint8_t> data() const { return {buf_.data(), len_}; }
  void reset() {
    len_ = 0;
    in_progress_ = false;
  }

 private:
  std::size_t expected_ = 0;
  std::array<std::uint8_t, 64 * kIoFragmentData> buf_{};
  std::size_t len_ = 0;
  bool in_progress_ = false;
  std::uint8_t next_count_ = 0;
};

// Duplicate MAC ID check message (Group 2 message 7, MAC = sender):
//   byte 0 bit7 = 1 response / 0 request, bits 6..0 physical port number;
//   bytes 1-2 vendor ID (LE); bytes 3-6 serial number (LE).
struct DupMac {
  bool response = false;
  std::uint8_t port = 0;
  std::uint16_t vendor = 0;
  std::uint32_t serial = 0;
};
can::Frame build_dup_mac(std::uint8_t mac, const DupMac& m);
std::optional<DupMac> parse_dup_mac(const can::Frame& f);

}  // namespace plc::devicenet

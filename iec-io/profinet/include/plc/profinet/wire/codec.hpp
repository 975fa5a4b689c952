// Shared pieces of the PROFINET codec: the result every decoder returns and
// bounds-checked readers/writers over byte spans.
//
// Decoders never throw on frame input and never read past their span: a
// ByteReader that runs out of bytes remembers it and returns zeros from then
// on, and the decoder turns that into a WireStatus with a reason. Encoders
// into caller buffers (ByteWriter) likewise remember an overflow and write
// nothing past the end; the encoder then returns 0 / a failed status.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace plc::profinet {

enum class WireError : std::uint8_t {
  None = 0,
  Truncated,        // fewer bytes than the PDU or block says
  BadLength,        // a length field disagrees with the bytes or the layout
  BadBlockType,     // not the block type expected here
  BadBlockVersion,  // block version other than 1.0 (1.1 where the standard allows it)
  BadHeader,        // RPC/DCP/RTA header field out of range
  BadFrameId,       // FrameID not the one this decoder handles
  BadEtherType,     // not 0x8892 (resp. 0x0800 for IPv4)
  BadValue,         // a field value the standard does not allow
  BufferTooSmall,   // encoder: the caller's buffer is too small
};

// The outcome of a decoder. `reason` is a static string (no allocation):
// which field was wrong, for counters and logs.
struct WireStatus {
  WireError error = WireError::None;
  const char* reason = "";
  [[nodiscard]] bool ok() const { return error == WireError::None; }
  explicit operator bool() const { return ok(); }
};
inline constexpr WireStatus kWireOk{};
[[nodiscard]] inline WireStatus wire_fail(WireError e, const char* reason) { return {e, reason}; }
[[nodiscard]] const char* to_string(WireError e);

// Reads big-endian (network order) fields, or little-endian ones where the
// DCE/RPC data representation says so. Past the end: returns 0, sets failed().
class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> b) : b_(b) {}
  std::uint8_t u8();
  std::uint16_t u16();  // big-endian
  std::uint32_t u32();  // big-endian
  std::uint16_t u16(bool little_endian);
  std::uint32_t u32(bool little_endian);
  // The next n bytes (empty span and failed() if fewer remain).
  std::span<const std::uint8_t> bytes(std::size_t n);
  void skip(std::size_t n) { (void)bytes(n); }
  [[nodiscard]] std::size_t pos() const { return pos_; }
  [[nodiscard]] std::size_t remaining() const { return failed_ ? 0 : b_.size() - pos_; }
  [[nodiscard]] bool failed() const { return failed_; }
  [[nodiscard]] std::span<const std::uint8_t> rest() const {
    return failed_ ? std::span<const std::uint8_t>{} : b_.subspan(pos_);
  }

 private:
  bool take(std::size_t n);
  std::span<const std::uint8_t> b_;
  std::size_t pos_ = 0;
  bool failed_ = false;
};

// Writes into a caller buffer; past the end: writes nothing, sets failed().
class ByteWriter {
 public:
  explicit ByteWriter(std::span<std::uint8_t> b) : b_(b) {}
  void u8(std::uint8_t v);
  void u16(std::uint16_t v);  // big-endian
  void u32(std::uint32_t v);  // big-endian
  void u16(std::uint16_t v, bool little_endian);
  void u32(std::uint32_t v, bool little_endian);
  void bytes(std::span<const std::uint8_t> v);
  void zeros(std::size_t n);
  // Overwrites a big-endian u16 at an earlier position (length fields).
  void patch_u16(std::size_t at, std::uint16_t v);
  void patch_u32(std::size_t at, std::uint32_t v, bool little_endian = false);
  [[nodiscard]] std::size_t pos() const { return pos_; }
  [[nodiscard]] bool failed() const { return failed_; }
  [[nodiscard]] std::span<std::uint8_t> written() const { return b_.first(pos_); }

 private:
  std::uint8_t* take(std::size_t n);
  std::span<std::uint8_t> b_;
  std::size_t pos_ = 0;
  bool failed_ = false;
};

// Appends to a growing byte vector (the acyclic encoders: DCP, RPC, blocks,
// alarms; never used on the cyclic path). Big-endian unless told.
class ByteBuilder {
 public:
  explicit ByteBuilder(std::vector<std::uint8_t>& out) : out_(out) {}
  void u8(std::uint8_t v) { out_.push_back(v); }
  // Inline (a record exchange builds ~100 fields; the vector's capacity is
  // mostly kept, rpc.hpp *_to()). push_back, not insert: GCC 12 warns
  // falsely (-Wstringop-overflow) on an inlined insert into a new vector.
  void u16(std::uint16_t v, bool little_endian = false) {
    const auto hi = static_cast<std::uint8_t>(v >> 8), lo = static_cast<std::uint8_t>(v);
    out_.push_back(little_endian ? lo : hi);
    out_.push_back(little_endian ? hi : lo);
  }
  void u32(std::uint32_t v, bool little_endian = false) {
    for (std::size_t i = 0; i < 4; ++i)
      out_.push_back(static_cast<std::uint8_t>(v >> (little_endian ? 8 * i : 8 * (3 - i))));
  }
  void bytes(std::span<const std::uint8_t> v);
  void zeros(std::size_t n) { out_.insert(out_.end(), n, 0); }
  void patch_u16(std::size_t at, std::uint16_t v, bool little_endian = false);
  void patch_u32(std::size_t at, std::uint32_t v, bool little_endian = false);
  // Pads with zeros to a multiple of `align` counted from `from`.
  void align(std::size_t align, std::size_t from = 0);
  [[nodiscard]] std::size_t pos() const { return out_.size(); }
  std::vector<std::uint8_t>& out() { return out_; }

 private:
  std::vector<std::uint8_t>& out_;
};

}  // namespace plc::profinet

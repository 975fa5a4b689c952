// The recording format PLCREC05 (layout: plc/debug/recording.hpp):
// constants, explicit little-endian encoding into fixed-capacity buffers,
// a bounds-checked cursor for reading, and the value and hash encodings
// that the recorder, the reader and the replayer share.
#pragma once

#include <boost/endian/conversion.hpp>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>
#include <type_traits>
#include <vector>

#include "plc/debug/crc32.hpp"
#include "plc/detail/small_copy.hpp"
#include "plc/types.hpp"

namespace plc::debug::recfmt {

inline constexpr char kMagic[8] = {'P', 'L', 'C', 'R', 'E', 'C', '0', '5'};
inline constexpr std::size_t kHead = 5;  // u8 type, u32 payload length
inline constexpr std::size_t kTail = 4;  // u32 running CRC

enum Type : std::uint8_t {
  kHeader = 'H',
  kLatch = 'L',
  kMerge = 'M',
  kStop = 'T',
  kChange = 'C',
  kEnd = 'E'
};
// A change record's task for "the build in use when the recording starts".
inline constexpr std::uint16_t kNoTask = 0xFFFF;
// Room for a change record's report text.
inline constexpr std::uint32_t kMaxReportBytes = 1u << 20;

// Where in a scan a debugger write was made (and is made again in a replay).
enum Point : std::uint8_t {
  kAfterLatch = 0,
  kBeforePrograms = 1,
  kBeforeProgram = 2,  // with the program's index
  kAfterPrograms = 3,
  kBeforePublish = 4,
};
// What a debugger write changed.
enum Target : std::uint8_t { kGlobalImage = 0, kTaskImage = 1, kVariable = 2 };

// Bounds checked before anything is allocated or added. Times stay below
// 2^60 ns (36 years), so adding a period or a timer preset to one cannot
// overflow an int64.
inline constexpr std::int64_t kMaxTimeNs = std::int64_t(1) << 60;
inline constexpr std::uint32_t kMaxRecordBytes = 64u << 20;
inline constexpr std::uint32_t kMaxImageBytes = 16u << 20;
inline constexpr std::uint16_t kMaxPathBytes = 1024;
inline constexpr std::uint8_t kMaxDeviceState = 2;  // io::DeviceState::Fault

// A record under construction in a fixed-capacity buffer: the scan never
// allocates; a record that does not fit marks the buffer overflowed.
class Buf {
 public:
  void reserve_fixed(std::size_t capacity) { b_.resize(capacity); }
  void clear() {
    n_ = 0;
    overflow_ = false;
  }
  void bytes(const void* p, std::size_t n) {
    if (n > b_.size() - n_) {
      overflow_ = true;
      return;
    }
    // Inline: a scan's record is many fields and device telegrams of a few
    // bytes each, for which a call into the library's memcpy cost more
    // than the copy (no pointer is read for n = 0).
    ::plc::detail::copy_bytes(b_.data() + n_, static_cast<const std::uint8_t*>(p), n);
    n_ += n;
  }
  template <class U>
  void le(U v) {
    static_assert(std::is_integral_v<U>);
    const U x = boost::endian::native_to_little(v);
    bytes(&x, sizeof x);
  }
  void u8(std::uint8_t v) { bytes(&v, 1); }
  template <class U>
  void patch(std::size_t at, U v) {
    if (at + sizeof v > n_) return;
    const U x = boost::endian::native_to_little(v);
    std::memcpy(b_.data() + at, &x, sizeof x);
  }
  // Frame: begin() writes type and a length slot, end() fills the length
  // and leaves the CRC slot (the writer thread fills it in).
  void begin(Type type) {
    clear();
    u8(type);
    le(std::uint32_t{0});
  }
  void end() {
    patch(1, static_cast<std::uint32_t>(n_ - kHead));
    le(std::uint32_t{0});
  }
  // Room for up to n more bytes, to be written through a Put without a
  // check per field (a record whose fields add up to at most n), then
  // taken with advance_to(); null (and the buffer overflowed) if there is
  // none.
  [[nodiscard]] std::uint8_t* room(std::size_t n) {
    if (n > b_.size() - n_) {
      overflow_ = true;
      return nullptr;
    }
    return b_.data() + n_;
  }
  void advance_to(const std::uint8_t* end) { n_ = static_cast<std::size_t>(end - b_.data()); }
  [[nodiscard]] std::size_t size() const { return n_; }
  [[nodiscard]] bool overflow() const { return overflow_; }
  [[nodiscard]] std::span<const std::uint8_t> view() const { return {b_.data(), n_}; }

 private:
  std::vector<std::uint8_t> b_;
  std::size_t n_ = 0;
  bool overflow_ = false;
};

// Writes fields into room a Buf checked for once (Buf::room): a cursor in
// a register, where Buf's own writes reload its bounds after each byte
// stored (a byte store may alias them).
struct Put {
  std::uint8_t* p;
  template <class U>
  void le(U v) {
    static_assert(std::is_integral_v<U>);
    const U x = boost::endian::native_to_little(v);
    std::memcpy(p, &x, sizeof x);
    p += sizeof x;
  }
  void u8(std::uint8_t v) { *p++ = v; }
  void bytes(const void* s, std::size_t n) {
    ::plc::detail::copy_bytes(p, static_cast<const std::uint8_t*>(s), n);
    p += n;
  }
};

// Reads a checked payload; every read fails (false) past its end.
class In {
 public:
  explicit In(std::span<const std::uint8_t> s) : s_(s) {}
  template <class U>
  bool le(U& v) {
    if (left() < sizeof v) return false;
    std::memcpy(&v, s_.data() + at_, sizeof v);
    v = boost::endian::little_to_native(v);
    at_ += sizeof v;
    return true;
  }
  bool take(std::size_t n, std::span<const std::uint8_t>& out) {
    if (left() < n) return false;
    out = s_.subspan(at_, n);
    at_ += n;
    return true;
  }
  [[nodiscard]] std::size_t left() const { return s_.size() - at_; }
  [[nodiscard]] std::size_t pos() const { return at_; }
  // The bytes read since position `from`.
  [[nodiscard]] std::span<const std::uint8_t> since(std::size_t from) const {
    return s_.subspan(from, at_ - from);
  }

 private:
  std::span<const std::uint8_t> s_;
  std::size_t at_ = 0;
};

// A value of a registry variable, as stored: little-endian of its native
// size; a STRING as u8 length + characters; a BOOL as 0 or 1.
void put_value(Buf& b, VarType type, const void* native);
// Checks and decodes a stored value into `native` (size_of(type) bytes, or
// a STRING); false if it is malformed.
bool get_value(In& in, VarType type, void* native);
// Checks a stored value without decoding it.
bool skip_value(In& in, std::uint8_t type);

// CRC-32 of IEEE 802.3 (as zlib's crc32): a record's stored CRC is the CRC
// of every record's type, length and payload from the first record up to
// and including its own, i.e. zlib.crc32 continued over the records.
using RunningCrc = Crc32;

// The scan's outputs as the replay compares them: the global %Q and %M
// after the merge. Each area as 8-byte little-endian words (its tail
// zero-padded), numbered k = 0, 1, ... through %Q and on through %M; word k
// goes into lane k mod 4: h = (h ^ w) * 0x100000001b3, h ^= h >> 32, lane i
// starting at 0xcbf29ce484222325 + i. The result: lane 0 with lanes 1..3
// folded in the same way.
std::uint64_t image_hash(std::span<const std::uint8_t> q, std::span<const std::uint8_t> m);

// Words [begin, end) of %Q and %M numbered as image_hash numbers them
// (the recorder's image mirror compares them); a range lies in one area.
struct ImageWords {
  std::uint32_t begin = 0, end = 0;
};

}  // namespace plc::debug::recfmt

// Encoding and decoding of the PR5510 window fields: the 4-byte value field
// as DINT, REAL or STRING chunk in the bus byte order, the packed codes 4 and
// 5, and the 24 status bits of R[5..7]. Pure functions, no state: used by
// the FBs and by the simulated device alike.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "plc/fb/weighing/window_layout.hpp"
#include "plc/io/byte_order.hpp"
#include "plc/types.hpp"

namespace plc::weighing {

// §3: the only bus-specific difference is the order of bytes 0..3.
enum class Bus : std::uint8_t { Profibus = 0, DeviceNet = 1 };

constexpr io::ByteOrder byte_order(Bus b) {
  return b == Bus::Profibus ? io::ByteOrder::Big : io::ByteOrder::Little;
}

// ---- DINT (§4.1, two's complement) and REAL (§4.2, IEEE 754 single) ----
// [INFERRED] §4.2: REAL follows the same bytes-0..3 order rule as DINT.
inline DINT decode_dint(std::span<const std::uint8_t> window, Bus bus) {
  return io::load<std::int32_t>(window.data() + r::kValue, byte_order(bus));
}
inline void encode_dint(std::span<std::uint8_t> window, DINT v, Bus bus) {
  io::store<std::int32_t>(window.data() + w::kValue, v, byte_order(bus));
}
inline REAL decode_real(std::span<const std::uint8_t> window, Bus bus) {
  return io::load<float>(window.data() + r::kValue, byte_order(bus));
}
inline void encode_real(std::span<std::uint8_t> window, REAL v, Bus bus) {
  io::store<float>(window.data() + w::kValue, v, byte_order(bus));
}

// ---- STRING (§4.3): always 20 characters, sent as 5 x 4 characters ----
// [INFERRED] (§4.3 leaves it open): chunk k carries characters 4k..4k+3 and
// goes through code base+k (five consecutive codes); characters are ASCII,
// padded with spaces; character 4k is the most significant byte of the
// 32-bit field, so Profibus shows them in reading order and DeviceNet
// reverses them like any other value.
inline constexpr std::size_t kStringLength = 20;
inline constexpr std::size_t kStringChunks = 5;

inline std::uint32_t string_chunk(std::string_view s, std::size_t k) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const std::size_t pos = 4 * k + i;
    const char c = pos < s.size() && pos < kStringLength ? s[pos] : ' ';
    v = (v << 8) | static_cast<std::uint8_t>(c);
  }
  return v;
}
// Writes characters 4k..4k+3 of chunk value v into dst[4k..4k+3].
inline void put_string_chunk(char* dst20, std::size_t k, std::uint32_t v) {
  for (std::size_t i = 0; i < 4; ++i)
    dst20[4 * k + i] = static_cast<char>((v >> (24 - 8 * i)) & 0xFF);
}
// The 20 characters with trailing padding spaces removed.
inline std::string_view trim_string(const char* src20) {
  std::size_t n = kStringLength;
  while (n > 0 && (src20[n - 1] == ' ' || src20[n - 1] == '\0')) --n;
  return {src20, n};
}

// ---- packed codes 4 and 5 (§5.3) ----
// How the two 16-bit words RWrn0/RWrn1 of the packed tables sit in the
// 32-bit field ([AMBIG] 9). The spec recommends MsbFirst and asks for the
// choice to be configurable: MsbFirst gives (RWrn0 << 16) | RWrn1, so on
// Profibus R[0] = decimals; CcLink gives (RWrn1 << 16) | RWrn0.
enum class PackedOrder : std::uint8_t { MsbFirst = 0, CcLink = 1 };

inline std::uint32_t pack_words(std::uint16_t rwrn0, std::uint16_t rwrn1, PackedOrder o) {
  return o == PackedOrder::MsbFirst ? (std::uint32_t{rwrn0} << 16) | rwrn1
                                    : (std::uint32_t{rwrn1} << 16) | rwrn0;
}
inline std::uint16_t rwrn0_of(std::uint32_t v, PackedOrder o) {
  return static_cast<std::uint16_t>(o == PackedOrder::MsbFirst ? v >> 16 : v & 0xFFFF);
}
inline std::uint16_t rwrn1_of(std::uint32_t v, PackedOrder o) {
  return static_cast<std::uint16_t>(o == PackedOrder::MsbFirst ? v & 0xFFFF : v >> 16);
}

// Code 4: RWrn0 = decimals (upper) | unit (lower); RWrn1 = division d
// (upper) | last displayed error (lower).
struct FormatInfo {
  std::uint8_t decimals = 0;
  std::uint8_t unit = 0;  // Unit codes 2..5
  std::uint8_t division = 0;
  std::uint8_t last_error = 0;
  friend bool operator==(const FormatInfo&, const FormatInfo&) = default;
};
inline std::uint32_t pack_format(const FormatInfo& f, PackedOrder o = PackedOrder::MsbFirst) {
  return pack_words(static_cast<std::uint16_t>((f.decimals << 8) | f.unit),
                    static_cast<std::uint16_t>((f.division << 8) | f.last_error), o);
}
inline FormatInfo unpack_format(std::uint32_t v, PackedOrder o = PackedOrder::MsbFirst) {
  const std::uint16_t a = rwrn0_of(v, o), b = rwrn1_of(v, o);
  return {static_cast<std::uint8_t>(a >> 8), static_cast<std::uint8_t>(a & 0xFF),
          static_cast<std::uint8_t>(b >> 8), static_cast<std::uint8_t>(b & 0xFF)};
}

// Code 5: RWrn0 = model (PR5510 -> 55h 10h), RWrn1 = version (Rel 3.00 ->
// 03h 00h). [INFERRED] versions are BCD like the model: Rel 3.12 -> 03h 12h.
struct ModelInfo {
  std::uint16_t model = 0;
  std::uint16_t version = 0;
  friend bool operator==(const ModelInfo&, const ModelInfo&) = default;
};
inline std::uint32_t pack_model(const ModelInfo& m, PackedOrder o = PackedOrder::MsbFirst) {
  return pack_words(m.model, m.version, o);
}
inline ModelInfo unpack_model(std::uint32_t v, PackedOrder o = PackedOrder::MsbFirst) {
  return {rwrn0_of(v, o), rwrn1_of(v, o)};
}

// ---- status bits R[5..7] (§3.4): always valid, independent of the code ----
struct StatusBits {
  // R[5]
  bool Limit1 = false, Limit2 = false, Limit3 = false;
  bool Out1 = false, Out2 = false, Out3 = false;
  bool PowerFail = false, WriteActive = false;
  // R[6]
  bool TestActive = false, CalChanged = false, TareActive = false;
  bool Inp1 = false, Inp2 = false, Inp3 = false;
  bool CmdError = false, CmdBusy = false;
  // R[7]
  bool AduError = false, AboveFsd = false, Overload = false, BelowZero = false;
  bool CenterZero = false, InsideZsr = false, StandStill = false, Dimmed = false;

  friend bool operator==(const StatusBits&, const StatusBits&) = default;
  // §7.2: Adu Error, Over-load and Dimmed mean "weight invalid" for batching.
  [[nodiscard]] bool weight_invalid() const { return AduError || Overload || Dimmed; }
};

constexpr StatusBits decode_status(std::span<const std::uint8_t> rd) {
  const std::uint8_t b5 = rd[r::kStatus], b6 = rd[r::kCommand], b7 = rd[r::kWeighing];
  auto bit = [](std::uint8_t b, unsigned i) { return ((b >> i) & 1U) != 0; };
  StatusBits s;
  s.Limit1 = bit(b5, r5::kLimit1);
  s.Limit2 = bit(b5, r5::kLimit2);
  s.Limit3 = bit(b5, r5::kLimit3);
  s.Out1 = bit(b5, r5::kOut1);
  s.Out2 = bit(b5, r5::kOut2);
  s.Out3 = bit(b5, r5::kOut3);
  s.PowerFail = bit(b5, r5::kPowerFail);
  s.WriteActive = bit(b5, r5::kWriteActive);
  s.TestActive = bit(b6, r6::kTestActive);
  s.CalChanged = bit(b6, r6::kCalChanged);
  s.TareActive = bit(b6, r6::kTareActive);
  s.Inp1 = bit(b6, r6::kInp1);
  s.Inp2 = bit(b6, r6::kInp2);
  s.Inp3 = bit(b6, r6::kInp3);
  s.CmdError = bit(b6, r6::kCmdError);
  s.CmdBusy = bit(b6, r6::kCmdBusy);
  s.AduError = bit(b7, r7::kAduError);
  s.AboveFsd = bit(b7, r7::kAboveFsd);
  s.Overload = bit(b7, r7::kOverload);
  s.BelowZero = bit(b7, r7::kBelowZero);
  s.CenterZero = bit(b7, r7::kCenterZero);
  s.InsideZsr = bit(b7, r7::kInsideZsr);
  s.StandStill = bit(b7, r7::kStandStill);
  s.Dimmed = bit(b7, r7::kDimmed);
  return s;
}

// The inverse, for the simulated device.
inline void encode_status(const StatusBits& s, std::span<std::uint8_t> rd) {
  auto b = [](bool on, unsigned i) { return static_cast<std::uint8_t>(on ? 1U << i : 0U); };
  rd[r::kStatus] = b(s.Limit1, r5::kLimit1) | b(s.Limit2, r5::kLimit2) | b(s.Limit3, r5::kLimit3) |
                   b(s.Out1, r5::kOut1) | b(s.Out2, r5::kOut2) | b(s.Out3, r5::kOut3) |
                   b(s.PowerFail, r5::kPowerFail) | b(s.WriteActive, r5::kWriteActive);
  rd[r::kCommand] = b(s.TestActive, r6::kTestActive) | b(s.CalChanged, r6::kCalChanged) |
                    b(s.TareActive, r6::kTareActive) | b(s.Inp1, r6::kInp1) | b(s.Inp2, r6::kInp2) |
                    b(s.Inp3, r6::kInp3) | b(s.CmdError, r6::kCmdError) |
                    b(s.CmdBusy, r6::kCmdBusy);
  rd[r::kWeighing] = b(s.AduError, r7::kAduError) | b(s.AboveFsd, r7::kAboveFsd) |
                     b(s.Overload, r7::kOverload) | b(s.BelowZero, r7::kBelowZero) |
                     b(s.CenterZero, r7::kCenterZero) | b(s.InsideZsr, r7::kInsideZsr) |
                     b(s.StandStill, r7::kStandStill) | b(s.Dimmed, r7::kDimmed);
}

// Raw 32-bit field of a read window / for a write window in bus order (for
// the packed codes, which are not signed quantities).
inline std::uint32_t decode_raw(std::span<const std::uint8_t> window, Bus bus) {
  return io::load<std::uint32_t>(window.data() + r::kValue, byte_order(bus));
}
inline void encode_raw(std::span<std::uint8_t> window, std::uint32_t v, Bus bus) {
  io::store<std::uint32_t>(window.data() + w::kValue, v, byte_order(bus));
}

}  // namespace plc::weighing

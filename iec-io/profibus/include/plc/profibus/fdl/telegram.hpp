// PROFIBUS FDL (layer 2, IEC 61158-4-3 / EN 50170 vol. 2) telegrams: the
// formats SD1 (no data), SD2 (variable data), SD3 (8 data bytes), SD4
// (token) and the short acknowledgement SC, the frame check sequence, the
// function code with its frame count bit, and the address extension (DSAP /
// SSAP). Characters are UART characters (11 bits: start, 8 data LSB first,
// even parity, stop); this codec sees only the 8 data bits.
//
//   SD1: 10 DA SA FC FCS 16
//   SD2: 68 LE LEr 68 DA SA FC [DSAP SSAP] DU... FCS 16   LE = 3 + len(DAE SAE DU), 4..249
//   SD3: A2 DA SA FC [DSAP SSAP] DU... FCS 16            DAE+SAE+DU exactly 8 bytes
//   SD4: DC DA SA                                         token
//   SC:  E5                                               short acknowledgement
// FCS = the sum mod 256 of DA..DU. DA/SA bit 7 set: an address extension
// byte follows FC (DA's first, then SA's); in it bit 6 set = a segment
// address, clear = a SAP (0..63), bit 7 = another extension byte follows.
// Decoding never allocates; a Telegram holds its data unit in place.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace plc::profibus::fdl {

inline constexpr std::uint8_t kSd1 = 0x10;
inline constexpr std::uint8_t kSd2 = 0x68;
inline constexpr std::uint8_t kSd3 = 0xA2;
inline constexpr std::uint8_t kSd4 = 0xDC;
inline constexpr std::uint8_t kSc = 0xE5;
inline constexpr std::uint8_t kEd = 0x16;

inline constexpr std::uint8_t kBroadcast = 127;   // DA of a broadcast (SDN only)
inline constexpr std::uint8_t kMaxStation = 126;  // 126: the default of an unaddressed slave
inline constexpr std::uint8_t kAddressExt = 0x80;

// Function code (FC). Bit 6: request (1) or response (0).
inline constexpr std::uint8_t kFcRequest = 0x40;
inline constexpr std::uint8_t kFcFcb = 0x20;  // request: frame count bit
inline constexpr std::uint8_t kFcFcv = 0x10;  // request: FCB valid
inline constexpr std::uint8_t kFcFunction = 0x0F;
// Request functions (FC bits 0..3 with kFcRequest).
inline constexpr std::uint8_t kReqTimeEvent = 0x0;
inline constexpr std::uint8_t kReqSdaLow = 0x3;
inline constexpr std::uint8_t kReqSdnLow = 0x4;
inline constexpr std::uint8_t kReqSdaHigh = 0x5;
inline constexpr std::uint8_t kReqSdnHigh = 0x6;
inline constexpr std::uint8_t kReqDdb = 0x7;
inline constexpr std::uint8_t kReqFdlStatus = 0x9;
inline constexpr std::uint8_t kReqSrdLow = 0xC;
inline constexpr std::uint8_t kReqSrdHigh = 0xD;
inline constexpr std::uint8_t kReqIdent = 0xE;
inline constexpr std::uint8_t kReqLsapStatus = 0xF;
// Response functions (FC bits 0..3, kFcRequest clear).
inline constexpr std::uint8_t kResOk = 0x0;
inline constexpr std::uint8_t kResUserError = 0x1;      // UE
inline constexpr std::uint8_t kResNoResource = 0x2;     // RR
inline constexpr std::uint8_t kResNoService = 0x3;      // RS: SAP not activated
inline constexpr std::uint8_t kResDataLow = 0x8;        // DL
inline constexpr std::uint8_t kResNoData = 0x9;         // NR
inline constexpr std::uint8_t kResDataHigh = 0xA;       // DH (DP: diagnosis pending)
inline constexpr std::uint8_t kResDataLowNoRes = 0xC;   // RDL
inline constexpr std::uint8_t kResDataHighNoRes = 0xD;  // RDH
// Response FC bits 4..5: the answering station's type.
inline constexpr std::uint8_t kStationSlave = 0x00;
inline constexpr std::uint8_t kStationMasterNotReady = 0x10;
inline constexpr std::uint8_t kStationMasterReady = 0x20;
inline constexpr std::uint8_t kStationMasterInRing = 0x30;

// The largest data unit of an SD2 telegram (LE 249 - DA SA FC), address
// extension bytes included.
inline constexpr std::size_t kMaxDataUnit = 246;
// The longest telegram on the wire: 68 LE LEr 68 DA SA FC DU[246] FCS ED.
inline constexpr std::size_t kMaxTelegram = 4 + 3 + kMaxDataUnit + 2;

enum class Format : std::uint8_t { Sd1, Sd2, Sd3, Token, ShortAck };
const char* to_string(Format f);

struct Telegram {
  Format format = Format::Sd1;
  std::uint8_t da = 0;  // without the extension bit
  std::uint8_t sa = 0;
  std::uint8_t fc = 0;
  // SAPs (0..63) from the address extension; -1: none.
  std::int16_t dsap = -1;
  std::int16_t ssap = -1;
  // Segment addresses from the extension (0..63); -1: none.
  std::int16_t dseg = -1;
  std::int16_t sseg = -1;
  std::array<std::uint8_t, kMaxDataUnit> data{};
  std::uint8_t length = 0;  // data bytes (without the extension bytes)

  [[nodiscard]] std::span<const std::uint8_t> du() const { return {data.data(), length}; }
  [[nodiscard]] bool request() const { return (fc & kFcRequest) != 0; }
  [[nodiscard]] std::uint8_t function() const { return fc & kFcFunction; }
  // Copies `d` into the data unit; false if it does not fit beside the SAPs.
  bool set_data(std::span<const std::uint8_t> d);
};

// Builders of the common telegrams (the format follows from the data).
// A request or response with data (dsap/ssap -1: no address extension).
Telegram make_data(std::uint8_t da, std::uint8_t sa, std::uint8_t fc, std::int16_t dsap,
                   std::int16_t ssap, std::span<const std::uint8_t> data = {});
Telegram make_token(std::uint8_t da, std::uint8_t sa);
Telegram make_short_ack();

// The sum mod 256 of the bytes.
std::uint8_t fcs(std::span<const std::uint8_t> bytes);

// Writes the telegram; returns its length, 0 if it does not fit `out` or is
// malformed (data too long, an address above 127, a SAP above 63). The
// format is chosen from the data: SD1 without a data unit, SD3 with exactly
// eight bytes (extension bytes included), else SD2; `format` is ignored
// except for Token and ShortAck.
std::size_t encode(const Telegram& t, std::span<std::uint8_t> out);

enum class DecodeStatus : std::uint8_t {
  Ok,        // a whole, valid telegram: `consumed` bytes
  NeedMore,  // a valid beginning: wait for more bytes
  Bad,       // not a telegram at this position (`why`); resynchronise
};

struct DecodeResult {
  DecodeStatus status = DecodeStatus::NeedMore;
  std::size_t consumed = 0;
  const char* why = "";
};

// Decodes the telegram at the start of `in`.
DecodeResult decode(std::span<const std::uint8_t> in, Telegram& out);

}  // namespace plc::profibus::fdl

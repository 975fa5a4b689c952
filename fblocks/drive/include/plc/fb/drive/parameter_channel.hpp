// The PROFIdrive base-mode parameter channel of the E1 (spec §6.4, Tables
// 4.3.1.1 - 4.3.4.3; format codes Table 4.3.5.1; error numbers Table 4.3.6.1
// = spec §6.5). Pure encoding and decoding: the SINA_PARA-style block and
// the simulated drive's parameter server both use it.
//
// Transport: the request is written with a record Write and the response is
// fetched with a record Read on the same index. We use record index 47
// (0x002F) by default, see kParamRecordIndex below.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace plc::drive {

// Record index of the parameter channel. 47 (0x002F) is the PROFIdrive
// base-mode parameter access record as the DPV1 "data record 47" that
// Siemens' SINA_PARA/SINA_PARA_S and the drive libraries use, and that
// PROFINET PROFIdrive devices accept as well; the E1 manual names no index
// (spec §1.4, §10.3.19). The PROFINET-specific local index 0xB02E (and the
// global 0xB02F) named by the spec [STD] are accepted by the simulated drive
// too, and the FB takes the index as an input for drives that need another.
inline constexpr std::uint16_t kParamRecordIndex = 0x002F;
inline constexpr std::uint16_t kParamRecordIndexLocal = 0xB02E;
inline constexpr std::uint16_t kParamRecordIndexGlobal = 0xB02F;

enum class RequestId : std::uint8_t { Read = 0x01, Write = 0x02 };
// Response IDs: request ID for success, | 0x80 for failure; 0x80 alone for an
// unknown request ID (error 0x21).
inline constexpr std::uint8_t kResponseErrorFlag = 0x80;
inline constexpr std::uint8_t kAttributeValue = 0x10;

// Table 4.3.5.1.
enum class ParamFormat : std::uint8_t {
  Reserved = 0x00,
  Boolean = 0x01,
  Int8 = 0x02,
  Int16 = 0x03,
  Int32 = 0x04,
  Uint8 = 0x05,
  Uint16 = 0x06,
  Uint32 = 0x07,
  Float32 = 0x08,
  Byte = 0x41,
  Word = 0x42,
  DoubleWord = 0x43,
  Error = 0x44,
};
// Size in bytes of one value of `f` on the wire, 0 for reserved/Error codes.
constexpr std::size_t format_size(std::uint8_t f) {
  switch (f) {
    case 0x01:
    case 0x02:
    case 0x05:
    case 0x41:
      return 1;
    case 0x03:
    case 0x06:
    case 0x42:
      return 2;
    case 0x04:
    case 0x07:
    case 0x08:
    case 0x43:
      return 4;
    default:
      return 0;
  }
}
constexpr bool is_value_format(std::uint8_t f) { return format_size(f) != 0; }
// Signed formats sign-extend to 64 bits when decoded.
constexpr bool format_signed(std::uint8_t f) { return f == 0x02 || f == 0x03 || f == 0x04; }
const char* format_name(std::uint8_t f);

// Table 4.3.6.1 (spec §6.5): every error number of a negative response.
enum class ParamErrorNo : std::uint8_t {
  ImpermissibleParameterNumber = 0x00,
  ValueCannotBeChanged = 0x01,
  LimitExceeded = 0x02,
  FaultySubindex = 0x03,
  NoArray = 0x04,
  IncorrectDataType = 0x05,
  SettingNotPermitted = 0x06,
  DescriptionElementCannotBeChanged = 0x07,
  DescriptionDataNotAvailable = 0x09,
  NoOperationPriority = 0x0B,
  TextArrayNotAvailable = 0x0F,
  NotExecutableInOperatingState = 0x11,
  ImpermissibleValue = 0x14,
  ResponseTooLong = 0x15,
  ImpermissibleParameterAddress = 0x16,
  IllegalFormat = 0x17,
  NumberOfValuesNotConsistent = 0x18,
  AxisDoesNotExist = 0x19,
  TextElementCannotBeChanged = 0x20,
  ServiceNotSupported = 0x21,
  TooManyParameterRequests = 0x22,
  MultiParameterNotSupported = 0x23,
};
// Name of an error number as Table 4.3.6.1 gives it ("reserved" for the
// reserved and blank rows).
const char* param_error_text(std::uint16_t error_no);

// Pt/Ut number to PNU (spec §6.2): the digits are read as hex, so Pt317 ->
// 0x2317, Pt53A -> 0x253A, Ut095 -> 0x4095. Write the number as a hex
// literal: pt_pnu(0x317), ut_pnu(0x095).
constexpr std::uint16_t pt_pnu(std::uint16_t pt_hex) {
  return static_cast<std::uint16_t>(0x2000 + (pt_hex & 0x0FFF));
}
constexpr std::uint16_t ut_pnu(std::uint16_t ut_hex) {
  return static_cast<std::uint16_t>(0x4000 + (ut_hex & 0x0FFF));
}
// "Pt317", "pt53a", "Ut095", "0x3200", "16#3200", "945" -> PNU; 0xFFFF if the
// text is none of these.
std::uint16_t parse_pnu(std::string_view text);

// Most values one request or response can carry (240-byte record, 2-byte
// values after a 6-byte header).
inline constexpr std::size_t kParamMaxValues = 117;

// A single-parameter request (Tables 4.3.1.1, 4.3.2.1, 4.3.3.1, 4.3.4.1).
struct ParamRequest {
  std::uint8_t reference = 1;
  std::uint8_t request_id = 0x01;
  std::uint8_t do_id = 0;
  std::uint8_t num_parameters = 1;
  std::uint8_t attribute = kAttributeValue;
  std::uint8_t num_elements = 0;  // 0 for a simple value as the manual writes it
  std::uint16_t pnu = 0;
  std::uint16_t subindex = 0;
  // Write only:
  std::uint8_t format = 0;
  std::uint8_t num_values = 0;
  std::array<std::uint32_t, kParamMaxValues> values{};  // raw bit patterns

  // Bytes of the request; 0 if it does not fit `out`.
  std::size_t encode(std::span<std::uint8_t> out) const;
};

// Result of parsing a request on the drive side.
enum class ParseResult : std::uint8_t { Ok, TooShort, BadValues };
ParseResult decode_request(std::span<const std::uint8_t> in, ParamRequest& r);

// A response (Tables 4.3.1.2/3, 4.3.2.2/3, 4.3.3.2/3, 4.3.4.2/3).
struct ParamResponse {
  std::uint8_t reference = 0;
  std::uint8_t response_id = 0;
  std::uint8_t do_id = 0;
  std::uint8_t num_parameters = 1;
  std::uint8_t format = 0;  // absent in a positive write response
  std::uint8_t num_values = 0;
  std::uint16_t error_no = 0;  // valid when format == 0x44
  std::array<std::uint32_t, kParamMaxValues> values{};

  [[nodiscard]] bool negative() const { return (response_id & kResponseErrorFlag) != 0; }
  std::size_t encode(std::span<std::uint8_t> out) const;
};
// false if the bytes are not a well-formed response.
bool decode_response(std::span<const std::uint8_t> in, ParamResponse& r);

// Raw value <-> number for a format (sign extension, Float32 bit cast).
// double_to_raw keeps the low bits of the rounded value: check a value to be
// written with value_fits_format first.
double raw_to_double(std::uint32_t raw, std::uint8_t format);
std::uint32_t double_to_raw(double v, std::uint8_t format);
// True if `v` is finite and, rounded to the nearest integer for the integer
// formats, inside the range of `format` (Table 4.3.5.1: Boolean 0..1, Int8,
// Int16, Int32, Uint8/Byte, Uint16/Word, Uint32/Double word; Float32 up to
// its largest finite value). A write of a value that does not fit is
// refused, never wrapped (70000 as Uint16 would arrive as 4464).
bool value_fits_format(double v, std::uint8_t format);

}  // namespace plc::drive

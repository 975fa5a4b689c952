#include "plc/fb/drive/parameter_channel.hpp"

#include <bit>
#include <cctype>
#include <cmath>
#include <limits>

namespace plc::drive {

const char* format_name(std::uint8_t f) {
  switch (f) {
    case 0x01:
      return "Boolean";
    case 0x02:
      return "Int8";
    case 0x03:
      return "Int16";
    case 0x04:
      return "Int32";
    case 0x05:
      return "Uint8";
    case 0x06:
      return "Uint16";
    case 0x07:
      return "Uint32";
    case 0x08:
      return "Float32";
    case 0x41:
      return "Byte";
    case 0x42:
      return "Word";
    case 0x43:
      return "Double word";
    case 0x44:
      return "Error";
    default:
      return "reserved";
  }
}

const char* param_error_text(std::uint16_t e) {
  switch (e) {
    case 0x00:
      return "Impermissible parameter number";
    case 0x01:
      return "Parameter value cannot be changed";
    case 0x02:
      return "Low or high limit exceeded";
    case 0x03:
      return "Faulty subindex";
    case 0x04:
      return "No array";
    case 0x05:
      return "Incorrect data type";
    case 0x06:
      return "Setting not permitted (may only be reset)";
    case 0x07:
      return "Description element cannot be changed";
    case 0x09:
      return "Description data not available";
    case 0x0B:
      return "No operation priority";
    case 0x0F:
      return "Text array not available";
    case 0x11:
      return "Request cannot be executed because of operating state";
    case 0x14:
      return "Impermissible value";
    case 0x15:
      return "Response too long";
    case 0x16:
      return "Impermissible parameter address";
    case 0x17:
      return "Illegal format";
    case 0x18:
      return "Number of values not consistent";
    case 0x19:
      return "Axis/DO does not exist";
    case 0x20:
      return "Parameter text element cannot be changed";
    case 0x21:
      return "Service not supported";
    case 0x22:
      return "Too many parameter requests";
    case 0x23:
      return "Multi-parameter access not supported";
    default:
      return "reserved";
  }
}

std::uint16_t parse_pnu(std::string_view t) {
  auto hex_digits = [](std::string_view s, std::uint32_t& v) {
    if (s.empty() || s.size() > 4) return false;
    v = 0;
    for (char c : s) {
      const int d = std::isdigit(static_cast<unsigned char>(c))
                        ? c - '0'
                        : (std::isxdigit(static_cast<unsigned char>(c))
                               ? std::tolower(static_cast<unsigned char>(c)) - 'a' + 10
                               : -1);
      if (d < 0) return false;
      v = v * 16 + static_cast<std::uint32_t>(d);
    }
    return true;
  };
  std::uint32_t v = 0;
  if (t.size() > 2) {
    const char a = static_cast<char>(std::tolower(static_cast<unsigned char>(t[0])));
    const char b = static_cast<char>(std::tolower(static_cast<unsigned char>(t[1])));
    if ((a == 'p' || a == 'u') && b == 't') {
      if (!hex_digits(t.substr(2), v) || v > 0xFFF) return 0xFFFF;
      return a == 'p' ? pt_pnu(static_cast<std::uint16_t>(v))
                      : ut_pnu(static_cast<std::uint16_t>(v));
    }
    if (t.substr(0, 2) == "0x" || t.substr(0, 2) == "0X")
      return hex_digits(t.substr(2), v) ? static_cast<std::uint16_t>(v) : 0xFFFF;
    if (t.size() > 3 && t.substr(0, 3) == "16#")
      return hex_digits(t.substr(3), v) ? static_cast<std::uint16_t>(v) : 0xFFFF;
  }
  if (t.empty() || t.size() > 5) return 0xFFFF;
  v = 0;
  for (char c : t) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return 0xFFFF;
    v = v * 10 + static_cast<std::uint32_t>(c - '0');
  }
  return v <= 0xFFFE ? static_cast<std::uint16_t>(v) : 0xFFFF;
}

namespace {
void put_value(std::span<std::uint8_t> out, std::size_t off, std::uint32_t raw, std::size_t sz) {
  for (std::size_t i = 0; i < sz; ++i)
    out[off + i] = static_cast<std::uint8_t>(raw >> (8 * (sz - 1 - i)));
}
std::uint32_t get_value(std::span<const std::uint8_t> in, std::size_t off, std::size_t sz) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < sz; ++i) v = (v << 8) | in[off + i];
  return v;
}
// Value block length: n values of sz bytes, padded to an even length [STD].
std::size_t block_len(std::size_t n, std::size_t sz) { return (n * sz + 1) & ~std::size_t{1}; }
}  // namespace

std::size_t ParamRequest::encode(std::span<std::uint8_t> out) const {
  const bool write = request_id == static_cast<std::uint8_t>(RequestId::Write);
  const std::size_t sz = format_size(format);
  const std::size_t n = num_values > kParamMaxValues ? kParamMaxValues : num_values;
  const std::size_t len = write ? 12 + block_len(n, sz ? sz : 0) : 10;
  if (out.size() < len) return 0;
  out[0] = reference;
  out[1] = request_id;
  out[2] = do_id;
  out[3] = num_parameters;
  out[4] = attribute;
  out[5] = num_elements;
  out[6] = static_cast<std::uint8_t>(pnu >> 8);
  out[7] = static_cast<std::uint8_t>(pnu);
  out[8] = static_cast<std::uint8_t>(subindex >> 8);
  out[9] = static_cast<std::uint8_t>(subindex);
  if (write) {
    out[10] = format;
    out[11] = num_values;
    for (std::size_t i = 0; i < n; ++i) put_value(out, 12 + i * sz, values[i], sz);
    if ((n * sz) & 1) out[12 + n * sz] = 0;
  }
  return len;
}

ParseResult decode_request(std::span<const std::uint8_t> in, ParamRequest& r) {
  if (in.size() < 4) return ParseResult::TooShort;
  r.reference = in[0];
  r.request_id = in[1];
  r.do_id = in[2];
  r.num_parameters = in[3];
  if (in.size() < 10) return ParseResult::TooShort;
  r.attribute = in[4];
  r.num_elements = in[5];
  r.pnu = static_cast<std::uint16_t>((in[6] << 8) | in[7]);
  r.subindex = static_cast<std::uint16_t>((in[8] << 8) | in[9]);
  r.format = 0;
  r.num_values = 0;
  if (r.request_id != static_cast<std::uint8_t>(RequestId::Write)) return ParseResult::Ok;
  if (in.size() < 12) return ParseResult::BadValues;
  r.format = in[10];
  r.num_values = in[11];
  const std::size_t sz = format_size(r.format);
  if (sz == 0) return ParseResult::Ok;  // the server answers "illegal format"
  if (r.num_values > kParamMaxValues || in.size() < 12 + r.num_values * sz)
    return ParseResult::BadValues;
  for (std::size_t i = 0; i < r.num_values; ++i) r.values[i] = get_value(in, 12 + i * sz, sz);
  return ParseResult::Ok;
}

std::size_t ParamResponse::encode(std::span<std::uint8_t> out) const {
  if (out.size() < 4) return 0;
  out[0] = reference;
  out[1] = response_id;
  out[2] = do_id;
  out[3] = num_parameters;
  if (response_id == static_cast<std::uint8_t>(RequestId::Write)) return 4;  // Table 4.3.2.2
  if (out.size() < 8) return 0;
  out[4] = format;
  out[5] = num_values;
  if (format == static_cast<std::uint8_t>(ParamFormat::Error)) {
    out[6] = static_cast<std::uint8_t>(error_no >> 8);
    out[7] = static_cast<std::uint8_t>(error_no);
    return 8;
  }
  const std::size_t sz = format_size(format);
  const std::size_t len = 6 + block_len(num_values, sz);
  if (out.size() < len) return 0;
  for (std::size_t i = 0; i < num_values; ++i) put_value(out, 6 + i * sz, values[i], sz);
  if ((num_values * sz) & 1) out[6 + num_values * sz] = 0;
  return len;
}

bool decode_response(std::span<const std::uint8_t> in, ParamResponse& r) {
  if (in.size() < 4) return false;
  r.reference = in[0];
  r.response_id = in[1];
  r.do_id = in[2];
  r.num_parameters = in[3];
  r.format = 0;
  r.num_values = 0;
  r.error_no = 0;
  if (r.response_id == static_cast<std::uint8_t>(RequestId::Write)) return true;
  if (in.size() < 6) return false;
  r.format = in[4];
  r.num_values = in[5];
  if (r.format == static_cast<std::uint8_t>(ParamFormat::Error)) {
    if (in.size() < 8) return false;
    r.error_no = static_cast<std::uint16_t>((in[6] << 8) | in[7]);
    return r.negative();
  }
  if (r.negative()) return false;  // a negative response must carry format 0x44
  const std::size_t sz = format_size(r.format);
  if (sz == 0 || r.num_values > kParamMaxValues || in.size() < 6 + r.num_values * sz) return false;
  for (std::size_t i = 0; i < r.num_values; ++i) r.values[i] = get_value(in, 6 + i * sz, sz);
  return true;
}

double raw_to_double(std::uint32_t raw, std::uint8_t f) {
  switch (f) {
    case 0x02:
      return static_cast<std::int8_t>(raw & 0xFF);
    case 0x03:
      return static_cast<std::int16_t>(raw & 0xFFFF);
    case 0x04:
      return static_cast<std::int32_t>(raw);
    case 0x08:
      return std::bit_cast<float>(raw);
    case 0x01:
    case 0x05:
    case 0x41:
      return raw & 0xFF;
    case 0x06:
    case 0x42:
      return raw & 0xFFFF;
    default:
      return raw;
  }
}

std::uint32_t double_to_raw(double v, std::uint8_t f) {
  if (f == 0x08) return std::bit_cast<std::uint32_t>(static_cast<float>(v));
  if (std::isnan(v)) return 0;
  const auto i = static_cast<std::int64_t>(std::llround(v));
  switch (format_size(f)) {
    case 1:
      return static_cast<std::uint32_t>(i) & 0xFF;
    case 2:
      return static_cast<std::uint32_t>(i) & 0xFFFF;
    default:
      return static_cast<std::uint32_t>(i);
  }
}

bool value_fits_format(double v, std::uint8_t f) {
  if (!std::isfinite(v)) return false;
  if (f == static_cast<std::uint8_t>(ParamFormat::Float32))
    return std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max());
  const double r = std::round(v);
  double lo = 0, hi = 0;
  switch (f) {
    case 0x01:
      hi = 1;
      break;
    case 0x02:
      lo = -128;
      hi = 127;
      break;
    case 0x03:
      lo = -32768;
      hi = 32767;
      break;
    case 0x04:
      lo = -2147483648.0;
      hi = 2147483647.0;
      break;
    case 0x05:
    case 0x41:
      hi = 255;
      break;
    case 0x06:
    case 0x42:
      hi = 65535;
      break;
    case 0x07:
    case 0x43:
      hi = 4294967295.0;
      break;
    default:
      return false;  // not a value format
  }
  return r >= lo && r <= hi;
}

}  // namespace plc::drive

#include "plc/hmi/value_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "plc/iec_literal.hpp"

namespace plc::hmi {

std::string value_text(VarType t, const unsigned char* p) {
  if (t == VarType::STRING) {
    STRING s;
    std::memcpy(static_cast<void*>(&s), p, sizeof s);
    const std::size_t n = std::min(s.size(), STRING::capacity);
    const STRING clamped(std::string_view(s.c_str(), n));
    return format_value(VarType::STRING, &clamped);
  }
  // An aligned copy (values in a snapshot are packed), BOOL as 0/1.
  alignas(8) unsigned char v[8] = {};
  std::memcpy(v, p, size_of(t));
  if (t == VarType::BOOL) v[0] = v[0] != 0;
  return format_value(t, v);
}

double value_number(VarType t, const unsigned char* p) {
  auto get = [p]<class T>(T) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  };
  switch (t) {
    case VarType::BOOL:
      return p[0] != 0 ? 1.0 : 0.0;
    case VarType::SINT:
      return get(std::int8_t{});
    case VarType::INT:
      return get(std::int16_t{});
    case VarType::DINT:
      return get(std::int32_t{});
    case VarType::LINT:
      return get(std::int64_t{});
    case VarType::USINT:
    case VarType::BYTE:
      return get(std::uint8_t{});
    case VarType::UINT:
    case VarType::WORD:
      return get(std::uint16_t{});
    case VarType::UDINT:
    case VarType::DWORD:
      return get(std::uint32_t{});
    case VarType::ULINT:
    case VarType::LWORD:
      return get(std::uint64_t{});
    case VarType::REAL:
      return get(float{});
    case VarType::LREAL:
      return get(double{});
    case VarType::TIME:
      return get(std::int64_t{}) / 1e9;  // seconds
    default:
      return std::nan("");
  }
}

}  // namespace plc::hmi

#include "plc/iec_literal.hpp"

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

namespace plc {
namespace {

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return u;
}

std::string_view strip_type_prefix(std::string_view s) {
  // "INT#5", "WORD#16#FF", "TIME#1s": drop a leading TYPE# if the prefix is
  // alphabetic (a base prefix like 16# is digits).
  const auto hash = s.find('#');
  if (hash == std::string_view::npos || hash == 0) return s;
  for (std::size_t i = 0; i < hash; ++i)
    if (!std::isalpha(static_cast<unsigned char>(s[i])) && s[i] != '_') return s;
  return s.substr(hash + 1);
}

}  // namespace

namespace {

// The value of a TIME literal in ns, which may lie beyond the int64 range;
// nullopt when `s` is not a TIME literal.
std::optional<long double> time_literal_ns(std::string_view s) {
  std::string u = upper(s);
  std::string_view v = u;
  if (v.rfind("TIME#", 0) == 0)
    v.remove_prefix(5);
  else if (v.rfind("LTIME#", 0) == 0)
    v.remove_prefix(6);
  else if (v.rfind("T#", 0) == 0)
    v.remove_prefix(2);
  else if (v.rfind("LT#", 0) == 0)
    v.remove_prefix(3);
  bool neg = false;
  if (!v.empty() && v[0] == '-') {
    neg = true;
    v.remove_prefix(1);
  }
  if (v.empty()) return std::nullopt;
  long double total_ns = 0;
  bool any = false;
  while (!v.empty()) {
    // number (may have a fraction and underscores)
    std::string num;
    std::size_t i = 0;
    while (i < v.size() &&
           (std::isdigit(static_cast<unsigned char>(v[i])) || v[i] == '.' || v[i] == '_')) {
      if (v[i] != '_') num.push_back(v[i]);
      ++i;
    }
    if (num.empty()) return std::nullopt;
    v.remove_prefix(i);
    long double unit = 0;
    if (v.rfind("MS", 0) == 0) {
      unit = 1e6L;
      v.remove_prefix(2);
    } else if (v.rfind("US", 0) == 0) {
      unit = 1e3L;
      v.remove_prefix(2);
    } else if (v.rfind("NS", 0) == 0) {
      unit = 1.0L;
      v.remove_prefix(2);
    } else if (v.rfind("D", 0) == 0) {
      unit = 86400e9L;
      v.remove_prefix(1);
    } else if (v.rfind("H", 0) == 0) {
      unit = 3600e9L;
      v.remove_prefix(1);
    } else if (v.rfind("M", 0) == 0) {
      unit = 60e9L;
      v.remove_prefix(1);
    } else if (v.rfind("S", 0) == 0) {
      unit = 1e9L;
      v.remove_prefix(1);
    } else
      return std::nullopt;
    char* end = nullptr;
    const long double x = std::strtold(num.c_str(), &end);
    if (end != num.c_str() + num.size()) return std::nullopt;
    total_ns += x * unit;
    any = true;
    if (!v.empty() && v[0] == '_') v.remove_prefix(1);
  }
  if (!any) return std::nullopt;
  return neg ? -total_ns : total_ns;
}

}  // namespace

std::optional<TIME> parse_iec_time(std::string_view s) {
  const auto total_ns = time_literal_ns(s);
  if (!total_ns ||
      std::fabs(*total_ns) > static_cast<long double>(std::numeric_limits<std::int64_t>::max()))
    return std::nullopt;
  return TIME(static_cast<std::int64_t>(std::llround(*total_ns)));
}

std::string iec_time_error(std::string_view s) {
  const auto total_ns = time_literal_ns(s);
  if (!total_ns) return "not a TIME (e.g. T#1s500ms): '" + std::string(s) + "'";
  if (!parse_iec_time(s))
    return "out of range for TIME (" + format_iec_time(TIME::min() + TIME(1)) + " .. " +
           format_iec_time(TIME::max()) + "): " + std::string(s);
  return {};
}

std::optional<std::uint64_t> parse_iec_unsigned(std::string_view s0) {
  std::string u = upper(strip_type_prefix(s0));
  if (u == "TRUE") return 1;
  if (u == "FALSE") return 0;
  int base = 10;
  std::string_view v = u;
  if (v.rfind("16#", 0) == 0) {
    base = 16;
    v.remove_prefix(3);
  } else if (v.rfind("8#", 0) == 0) {
    base = 8;
    v.remove_prefix(2);
  } else if (v.rfind("2#", 0) == 0) {
    base = 2;
    v.remove_prefix(2);
  } else if (v.rfind("0X", 0) == 0) {
    base = 16;
    v.remove_prefix(2);
  }
  std::string digits;
  for (char c : v)
    if (c != '_') digits.push_back(c);
  if (digits.empty()) return std::nullopt;
  std::uint64_t x = 0;
  auto [p, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), x, base);
  if (ec != std::errc() || p != digits.data() + digits.size()) return std::nullopt;
  return x;
}

std::optional<std::int64_t> parse_iec_integer(std::string_view s0) {
  std::string_view s = strip_type_prefix(s0);
  bool neg = false;
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) {
    neg = s[0] == '-';
    s.remove_prefix(1);
  }
  auto u = parse_iec_unsigned(s);
  if (!u) return std::nullopt;
  if (neg) {
    if (*u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) + 1)
      return std::nullopt;
    return static_cast<std::int64_t>(0 - *u);
  }
  if (*u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
    return std::nullopt;
  return static_cast<std::int64_t>(*u);
}

std::optional<double> parse_iec_real(std::string_view s0) {
  std::string digits;
  for (char c : strip_type_prefix(s0))
    if (c != '_') digits.push_back(c);
  if (digits.empty()) return std::nullopt;
  char* end = nullptr;
  const double d = std::strtod(digits.c_str(), &end);
  if (end != digits.c_str() + digits.size() || !std::isfinite(d)) return std::nullopt;
  return d;
}

std::string format_iec_time(TIME t) {
  std::int64_t ns = t.count();
  std::string out = "T#";
  if (ns < 0) {
    out += '-';
    ns = -ns;
  }
  if (ns == 0) return out + "0s";
  struct Unit {
    std::int64_t size;
    const char* name;
  };
  static constexpr Unit units[] = {{86400'000'000'000LL, "d"},
                                   {3600'000'000'000LL, "h"},
                                   {60'000'000'000LL, "m"},
                                   {1'000'000'000LL, "s"},
                                   {1'000'000LL, "ms"},
                                   {1'000LL, "us"},
                                   {1LL, "ns"}};
  for (const Unit& u : units) {
    if (ns >= u.size) {
      out += std::to_string(ns / u.size);
      out += u.name;
      ns %= u.size;
    }
  }
  return out;
}

namespace {

// "out of range for USINT (0 .. 255): 300"
std::string out_of_range(VarType type, const std::string& lo, const std::string& hi,
                         std::string_view text) {
  return "out of range for " + std::string(to_string(type)) + " (" + lo + " .. " + hi +
         "): " + std::string(text);
}

// A well-formed integer literal (sign, base, digits): when it does not
// parse as the type's integer it is out of range (too big for 64 bits, or
// negative for an unsigned type), not a syntax error.
bool integer_syntax(std::string_view text) {
  std::string_view t = strip_type_prefix(text);
  if (!t.empty() && (t[0] == '-' || t[0] == '+')) t.remove_prefix(1);
  int base = 10;
  for (auto [prefix, b] : {std::pair{"16#", 16}, {"8#", 8}, {"2#", 2}}) {
    if (t.starts_with(prefix)) {
      base = b;
      t.remove_prefix(std::string_view(prefix).size());
    }
  }
  bool any = false;
  for (char c : t) {
    if (c == '_') continue;
    const int d = std::isdigit(static_cast<unsigned char>(c)) ? c - '0'
                  : std::isxdigit(static_cast<unsigned char>(c))
                      ? std::toupper(static_cast<unsigned char>(c)) - 'A' + 10
                      : 99;
    if (d >= base) return false;
    any = true;
  }
  return any;
}

template <class T>
std::string store_int(VarType type, std::string_view text, void* dst) {
  using L = std::numeric_limits<T>;
  const auto range = [&] {
    return out_of_range(type, std::to_string(L::min()), std::to_string(L::max()), text);
  };
  if constexpr (std::is_signed_v<T>) {
    auto v = parse_iec_integer(text);
    if (!v) return integer_syntax(text) ? range() : "not an integer: '" + std::string(text) + "'";
    if (*v < L::min() || *v > L::max()) return range();
    *static_cast<T*>(dst) = static_cast<T>(*v);
  } else {
    auto v = parse_iec_unsigned(text);
    if (!v)
      return integer_syntax(text) ? range()
                                  : "not an unsigned integer: '" + std::string(text) + "'";
    if (*v > L::max()) return range();
    *static_cast<T*>(dst) = static_cast<T>(*v);
  }
  return {};
}

// REAL and LREAL: finite values within the type's range. A double that
// rounds to infinity as a REAL is out of range; 3.40282347e+38 (FLT_MAX as
// printed) still rounds to FLT_MAX and is accepted.
std::string store_real(VarType type, std::string_view text, void* dst) {
  const bool single = type == VarType::REAL;
  const std::string max_text = single ? "3.40282347e+38" : "1.7976931348623157e+308";
  auto d = parse_iec_real(text);
  if (!d) {
    std::string digits;
    for (char c : strip_type_prefix(text))
      if (c != '_') digits.push_back(c);
    char* end = nullptr;
    errno = 0;
    const double x = digits.empty() ? 0.0 : std::strtod(digits.c_str(), &end);
    const bool number = !digits.empty() && end == digits.c_str() + digits.size();
    if (number && std::isnan(x))
      return std::string("not a number: '") + std::string(text) + "' (" + to_string(type) +
             " values are finite)";
    const std::string a_type = single ? "a REAL" : "an LREAL";
    if (number && std::isinf(x) && errno != ERANGE)
      return "infinity is not " + a_type + " value: '" + std::string(text) + "'";
    if (number) return out_of_range(type, "-" + max_text, max_text, text);
    return "not " + a_type + ": '" + std::string(text) + "'";
  }
  if (single) {
    // 2^128 - 2^103: from here on the nearest float is infinity.
    constexpr double kRealOverflow = 0x1.ffffffp127;
    if (std::fabs(*d) >= kRealOverflow) return out_of_range(type, "-" + max_text, max_text, text);
    *static_cast<float*>(dst) = static_cast<float>(*d);
  } else {
    *static_cast<double*>(dst) = *d;
  }
  return {};
}

// The text of an integer, as std::to_string makes it, appended.
template <class T>
void append_int(std::string& out, T v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

// "16#" and `digits` upper-case hex digits at least: printf's "%0*llX"
// (digits <= 16), built in a buffer and appended once.
void append_hex(std::string& out, std::uint64_t v, int digits) {
  char hex[16];
  const auto r = std::to_chars(hex, hex + sizeof hex, v, 16);
  const auto n = static_cast<int>(r.ptr - hex);
  char buf[3 + 16] = {'1', '6', '#'};
  int k = 3;
  for (int pad = digits - n; pad > 0; --pad) buf[k++] = '0';
  for (int i = 0; i < n; ++i)
    buf[k++] = (hex[i] >= 'a') ? static_cast<char>(hex[i] - 'a' + 'A') : hex[i];
  out.append(buf, static_cast<std::size_t>(k));
}

// printf's "%.*g" (std::to_chars with a precision is specified as printf
// in the C locale, and is several times cheaper: the trace's writer formats
// every value of every row), then ".0" when the text looks like an integer.
// Test: IecLiteral.FormattedRealsAndHexAreThePrintfTexts.
void append_real(std::string& out, double d, int precision) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, d, std::chars_format::general, precision);
  const std::string_view s(buf, static_cast<std::size_t>(r.ptr - buf));
  out += s;
  if (s.find_first_of(".eEni") == std::string_view::npos) out += ".0";
}

}  // namespace

std::string parse_value(VarType type, std::string_view text, void* dst) {
  switch (type) {
    case VarType::BOOL: {
      const std::string u = upper(text);
      if (u == "TRUE" || u == "1")
        *static_cast<bool*>(dst) = true;
      else if (u == "FALSE" || u == "0")
        *static_cast<bool*>(dst) = false;
      else
        return "not a BOOL (TRUE/FALSE): '" + std::string(text) + "'";
      return {};
    }
    case VarType::SINT:
      return store_int<std::int8_t>(type, text, dst);
    case VarType::INT:
      return store_int<std::int16_t>(type, text, dst);
    case VarType::DINT:
      return store_int<std::int32_t>(type, text, dst);
    case VarType::LINT:
      return store_int<std::int64_t>(type, text, dst);
    case VarType::USINT:
    case VarType::BYTE:
      return store_int<std::uint8_t>(type, text, dst);
    case VarType::UINT:
    case VarType::WORD:
      return store_int<std::uint16_t>(type, text, dst);
    case VarType::UDINT:
    case VarType::DWORD:
      return store_int<std::uint32_t>(type, text, dst);
    case VarType::ULINT:
    case VarType::LWORD:
      return store_int<std::uint64_t>(type, text, dst);
    case VarType::REAL:
    case VarType::LREAL:
      return store_real(type, text, dst);
    case VarType::TIME: {
      auto t = parse_iec_time(text);
      if (!t) return iec_time_error(text);
      *static_cast<TIME*>(dst) = *t;
      return {};
    }
    case VarType::STRING: {
      std::string_view v = text;
      if (v.size() >= 2 && v.front() == '\'' && v.back() == '\'') v = v.substr(1, v.size() - 2);
      // An external write is refused rather than cut (FixedString cuts only
      // inside a scan, where nothing may fail).
      if (v.size() > STRING::capacity)
        return "too long for STRING (" + std::to_string(STRING::capacity) +
               " characters at most): " + std::to_string(v.size()) + " characters";
      static_cast<STRING*>(dst)->assign(v);
      return {};
    }
  }
  return "unknown type";
}

std::string check_raw_value(VarType type, const void* src) {
  switch (type) {
    case VarType::BOOL: {
      std::uint8_t b = 0;
      std::memcpy(&b, src, 1);
      return b <= 1 ? std::string() : "not a BOOL: byte " + std::to_string(b) + " (0 or 1)";
    }
    case VarType::REAL:
    case VarType::LREAL: {
      double d = 0;
      if (type == VarType::REAL) {
        float f = 0;
        std::memcpy(&f, src, sizeof f);
        d = f;
      } else {
        std::memcpy(&d, src, sizeof d);
      }
      if (std::isnan(d))
        return std::string("not a number (") + to_string(type) + " values are finite)";
      if (std::isinf(d))
        return std::string("infinity is not ") + (type == VarType::REAL ? "a REAL" : "an LREAL") +
               " value";
      return {};
    }
    case VarType::STRING:
      return "a STRING is not written as bytes";
    default:
      return {};
  }
}

void append_value(std::string& out, VarType type, const void* src) {
  switch (type) {
    case VarType::BOOL:
      out += *static_cast<const bool*>(src) ? "TRUE" : "FALSE";
      return;
    case VarType::SINT:
      return append_int(out, *static_cast<const std::int8_t*>(src));
    case VarType::INT:
      return append_int(out, *static_cast<const std::int16_t*>(src));
    case VarType::DINT:
      return append_int(out, *static_cast<const std::int32_t*>(src));
    case VarType::LINT:
      return append_int(out, *static_cast<const std::int64_t*>(src));
    case VarType::USINT:
      return append_int(out, *static_cast<const std::uint8_t*>(src));
    case VarType::UINT:
      return append_int(out, *static_cast<const std::uint16_t*>(src));
    case VarType::UDINT:
      return append_int(out, *static_cast<const std::uint32_t*>(src));
    case VarType::ULINT:
      return append_int(out, *static_cast<const std::uint64_t*>(src));
    case VarType::BYTE:
      return append_hex(out, *static_cast<const std::uint8_t*>(src), 2);
    case VarType::WORD:
      return append_hex(out, *static_cast<const std::uint16_t*>(src), 4);
    case VarType::DWORD:
      return append_hex(out, *static_cast<const std::uint32_t*>(src), 8);
    case VarType::LWORD:
      return append_hex(out, *static_cast<const std::uint64_t*>(src), 16);
    case VarType::REAL:
      return append_real(out, *static_cast<const float*>(src), 9);
    case VarType::LREAL:
      return append_real(out, *static_cast<const double*>(src), 17);
    case VarType::TIME:
      out += format_iec_time(*static_cast<const TIME*>(src));
      return;
    case VarType::STRING:
      out += '\'';
      out += static_cast<const STRING*>(src)->view();
      out += '\'';
      return;
  }
  out += '?';
}

std::string format_value(VarType type, const void* src) {
  std::string out;
  append_value(out, type, src);
  return out;
}

}  // namespace plc

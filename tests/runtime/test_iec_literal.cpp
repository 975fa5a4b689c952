// IEC 61131-3 §6.3.3 literals: duration (T#), integer with base prefix,
// typed literals; and printing in IEC notation.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "plc/iec_literal.hpp"

using namespace plc;
using namespace std::chrono_literals;

TEST(IecLiteral, ParsesDurations) {
  EXPECT_EQ(*parse_iec_time("T#1s500ms"), 1500ms);
  EXPECT_EQ(*parse_iec_time("t#20ms"), 20ms);
  EXPECT_EQ(*parse_iec_time("TIME#1h2m3s"), 1h + 2min + 3s);
  EXPECT_EQ(*parse_iec_time("1.5s"), 1500ms);
  EXPECT_EQ(*parse_iec_time("T#-20ms"), -20ms);
  EXPECT_EQ(*parse_iec_time("250us"), 250us);
  EXPECT_EQ(*parse_iec_time("T#1d"), 24h);
  EXPECT_EQ(*parse_iec_time("T#1m_30s"), 90s);
  EXPECT_FALSE(parse_iec_time("20"));
  EXPECT_FALSE(parse_iec_time("T#"));
  EXPECT_FALSE(parse_iec_time("5 parsecs"));
}

TEST(IecLiteral, FormatsDurations) {
  EXPECT_EQ(format_iec_time(1500ms), "T#1s500ms");
  EXPECT_EQ(format_iec_time(0ms), "T#0s");
  EXPECT_EQ(format_iec_time(-20ms), "T#-20ms");
  EXPECT_EQ(format_iec_time(1h + 1us), "T#1h1us");
}

TEST(IecLiteral, ParsesIntegers) {
  EXPECT_EQ(*parse_iec_integer("16#047F"), 0x047F);
  EXPECT_EQ(*parse_iec_integer("2#1010_0101"), 0xA5);
  EXPECT_EQ(*parse_iec_integer("8#17"), 15);
  EXPECT_EQ(*parse_iec_integer("-1_000"), -1000);
  EXPECT_EQ(*parse_iec_integer("INT#-5"), -5);
  EXPECT_EQ(*parse_iec_integer("WORD#16#FF"), 255);
  EXPECT_EQ(*parse_iec_integer("TRUE"), 1);
  EXPECT_FALSE(parse_iec_integer("12abc"));
  EXPECT_FALSE(parse_iec_integer(""));
}

TEST(IecLiteral, ValuesRoundTripInIecNotation) {
  struct Row {
    VarType type;
    const char* in;
    const char* out;
  };
  const Row rows[] = {
      {VarType::BOOL, "TRUE", "TRUE"},      {VarType::BOOL, "0", "FALSE"},
      {VarType::SINT, "-128", "-128"},      {VarType::INT, "16#7FFF", "32767"},
      {VarType::DINT, "-5", "-5"},          {VarType::UINT, "65535", "65535"},
      {VarType::BYTE, "255", "16#FF"},      {VarType::WORD, "16#047F", "16#047F"},
      {VarType::DWORD, "1", "16#00000001"}, {VarType::REAL, "1.5", "1.5"},
      {VarType::LREAL, "2", "2.0"},         {VarType::TIME, "T#1s500ms", "T#1s500ms"},
      {VarType::STRING, "'abc'", "'abc'"},  {VarType::LWORD, "16#1", "16#0000000000000001"},
  };
  for (const Row& r : rows) {
    alignas(8) unsigned char buf[sizeof(STRING)] = {};
    void* p = buf;
    if (r.type == VarType::STRING) p = new (buf) STRING();
    ASSERT_EQ(parse_value(r.type, r.in, p), "") << r.in;
    EXPECT_EQ(format_value(r.type, p), r.out) << r.in;
  }
}

TEST(IecLiteral, RejectsOutOfRangeAndWrongType) {
  std::int16_t i = 0;
  EXPECT_NE(parse_value(VarType::INT, "40000", &i), "");
  std::uint8_t b = 0;
  EXPECT_NE(parse_value(VarType::USINT, "-1", &b), "");
  bool x = false;
  EXPECT_NE(parse_value(VarType::BOOL, "yes", &x), "");
  TIME t{};
  EXPECT_NE(parse_value(VarType::TIME, "12", &t), "");
}

// Issue 10 point 7: a value beyond its type's range is refused with an error
// that names the range (IEC 61131-3 Table 10 ranges of the elementary types;
// REAL/LREAL are IEC 60559 single/double), never stored as ±inf or wrapped.
TEST(IecLiteral, RealsBeyondTheirRangeAreRefusedNamingTheRange) {
  float f = 1.0F;
  EXPECT_EQ(parse_value(VarType::REAL, "1e39", &f),
            "out of range for REAL (-3.40282347e+38 .. 3.40282347e+38): 1e39");
  EXPECT_EQ(parse_value(VarType::REAL, "-1e39", &f),
            "out of range for REAL (-3.40282347e+38 .. 3.40282347e+38): -1e39");
  EXPECT_EQ(f, 1.0F) << "a refused value is not stored";
  // FLT_MAX as printed (9 digits) is slightly above FLT_MAX yet rounds to it.
  ASSERT_EQ(parse_value(VarType::REAL, "3.40282347e+38", &f), "");
  EXPECT_EQ(f, std::numeric_limits<float>::max());
  ASSERT_EQ(parse_value(VarType::REAL, "-3.40282347e38", &f), "");
  EXPECT_EQ(f, -std::numeric_limits<float>::max());
  f = 1.0F;
  double d = 1.0;
  EXPECT_EQ(parse_value(VarType::LREAL, "1e309", &d),
            "out of range for LREAL (-1.7976931348623157e+308 .. 1.7976931348623157e+308): 1e309");
  EXPECT_EQ(parse_value(VarType::LREAL, "REAL#-1e309", &d),
            "out of range for LREAL (-1.7976931348623157e+308 .. 1.7976931348623157e+308): "
            "REAL#-1e309");
  ASSERT_EQ(parse_value(VarType::LREAL, "1.7976931348623157e308", &d), "");
  EXPECT_EQ(d, std::numeric_limits<double>::max());
  for (const char* s : {"nan", "NaN", "-nan"}) {
    EXPECT_NE(parse_value(VarType::REAL, s, &f).find("not a number"), std::string::npos) << s;
    EXPECT_NE(parse_value(VarType::LREAL, s, &d).find("not a number"), std::string::npos) << s;
  }
  for (const char* s : {"inf", "-inf", "infinity", "INF"}) {
    EXPECT_NE(parse_value(VarType::REAL, s, &f).find("infinity is not a REAL value"),
              std::string::npos)
        << s;
    EXPECT_NE(parse_value(VarType::LREAL, s, &d).find("infinity is not an LREAL value"),
              std::string::npos)
        << s;
  }
  EXPECT_EQ(f, 1.0F);
  EXPECT_EQ(d, std::numeric_limits<double>::max());
  EXPECT_EQ(parse_value(VarType::REAL, "1.5x", &f), "not a REAL: '1.5x'");
}

TEST(IecLiteral, IntegersBeyondTheirRangeAreRefusedNamingTheRange) {
  struct Row {
    VarType type;
    const char* in;
    const char* error;
  };
  const Row rows[] = {
      {VarType::SINT, "128", "out of range for SINT (-128 .. 127): 128"},
      {VarType::SINT, "-129", "out of range for SINT (-128 .. 127): -129"},
      {VarType::INT, "40000", "out of range for INT (-32768 .. 32767): 40000"},
      {VarType::DINT, "-2147483649",
       "out of range for DINT (-2147483648 .. 2147483647): -2147483649"},
      {VarType::LINT, "9223372036854775808",
       "out of range for LINT (-9223372036854775808 .. 9223372036854775807): 9223372036854775808"},
      {VarType::LINT, "-99999999999999999999",
       "out of range for LINT (-9223372036854775808 .. 9223372036854775807): "
       "-99999999999999999999"},
      {VarType::USINT, "256", "out of range for USINT (0 .. 255): 256"},
      {VarType::USINT, "-1", "out of range for USINT (0 .. 255): -1"},
      {VarType::UINT, "16#10000", "out of range for UINT (0 .. 65535): 16#10000"},
      {VarType::UDINT, "4294967296", "out of range for UDINT (0 .. 4294967295): 4294967296"},
      {VarType::ULINT, "18446744073709551616",
       "out of range for ULINT (0 .. 18446744073709551615): 18446744073709551616"},
      {VarType::BYTE, "16#100", "out of range for BYTE (0 .. 255): 16#100"},
      {VarType::WORD, "70000", "out of range for WORD (0 .. 65535): 70000"},
      {VarType::DWORD, "-5", "out of range for DWORD (0 .. 4294967295): -5"},
      {VarType::LWORD, "16#1_0000_0000_0000_0000",
       "out of range for LWORD (0 .. 18446744073709551615): 16#1_0000_0000_0000_0000"},
      {VarType::INT, "12abc", "not an integer: '12abc'"},
      {VarType::UINT, "0x", "not an unsigned integer: '0x'"},
  };
  for (const Row& r : rows) {
    std::uint64_t v = 0x5A5A5A5A5A5A5A5AULL;
    EXPECT_EQ(parse_value(r.type, r.in, &v), r.error) << to_string(r.type) << " " << r.in;
    EXPECT_EQ(v, 0x5A5A5A5A5A5A5A5AULL) << "nothing stored: " << r.in;
  }
  std::int64_t l = 0;
  ASSERT_EQ(parse_value(VarType::LINT, "-9223372036854775808", &l), "");
  EXPECT_EQ(l, std::numeric_limits<std::int64_t>::min());
  std::uint64_t u = 0;
  ASSERT_EQ(parse_value(VarType::ULINT, "18446744073709551615", &u), "");
  EXPECT_EQ(u, std::numeric_limits<std::uint64_t>::max());
}

TEST(IecLiteral, TimesAndStringsBeyondTheirRangeAreRefused) {
  TIME t{7};
  EXPECT_EQ(parse_value(VarType::TIME, "T#200000d", &t),
            "out of range for TIME (T#-106751d23h47m16s854ms775us807ns .. "
            "T#106751d23h47m16s854ms775us807ns): T#200000d");
  EXPECT_EQ(parse_value(VarType::TIME, "T#-200000d", &t).rfind("out of range for TIME", 0), 0u);
  EXPECT_EQ(parse_value(VarType::TIME, "T#1x", &t), "not a TIME (e.g. T#1s500ms): 'T#1x'");
  EXPECT_EQ(t, TIME(7));
  ASSERT_EQ(parse_value(VarType::TIME, "T#106751d23h47m16s854ms775us807ns", &t), "");
  EXPECT_EQ(t, TIME::max());
  STRING s = "keep";
  EXPECT_EQ(parse_value(VarType::STRING, "'" + std::string(81, 'x') + "'", &s),
            "too long for STRING (80 characters at most): 81 characters");
  EXPECT_EQ(s.view(), "keep");
  ASSERT_EQ(parse_value(VarType::STRING, std::string(80, 'y'), &s), "");
  EXPECT_EQ(s.size(), 80u);
}

namespace {
// The texts format_value() made with printf before it used std::to_chars
// (runtime/src/iec_literal.cpp): "%.*g" plus ".0" when the text looks like
// an integer, and "16#%0*llX".
std::string printf_real(double d, int precision) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", precision, d);
  std::string s = buf;
  if (s.find_first_of(".eEni") == std::string::npos) s += ".0";
  return s;
}
std::string printf_hex(std::uint64_t v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "16#%0*llX", digits, static_cast<unsigned long long>(v));
  return buf;
}
}  // namespace

// Traces, the debugger and the HMI print values through format_value(); its
// REAL/LREAL and hex texts must stay byte for byte what printf made (golden
// traces compare them): random bit patterns (every exponent, subnormals,
// NaN payloads), the special values, and values near the precision's edge.
TEST(IecLiteral, FormattedRealsAndHexAreThePrintfTexts) {
  std::uint64_t x = 0x9E3779B97F4A7C15ULL;
  auto next = [&] {
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    return x * 0x2545F4914F6CDD1DULL;
  };
  std::vector<double> doubles = {0.0,
                                 -0.0,
                                 1.0,
                                 -1.0,
                                 0.1,
                                 1e16,
                                 1e17,
                                 123456789012345678.0,
                                 1e-5,
                                 1e-4,
                                 0.5e-4,
                                 std::numeric_limits<double>::min(),
                                 std::numeric_limits<double>::denorm_min(),
                                 std::numeric_limits<double>::max(),
                                 std::numeric_limits<double>::infinity(),
                                 -std::numeric_limits<double>::infinity(),
                                 std::numeric_limits<double>::quiet_NaN(),
                                 -std::numeric_limits<double>::quiet_NaN(),
                                 20.0100002,
                                 3950000.0};
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t bits = next();
    double d;
    std::memcpy(&d, &bits, sizeof d);
    doubles.push_back(d);
    doubles.push_back(static_cast<double>(static_cast<std::int64_t>(bits) >> (bits & 63)));
  }
  int checked = 0;
  for (const double d : doubles) {
    ASSERT_EQ(printf_real(d, 17), format_value(VarType::LREAL, &d))
        << "LREAL bits " << std::hex << std::bit_cast<std::uint64_t>(d);
    const auto f = static_cast<float>(d);
    ASSERT_EQ(printf_real(f, 9), format_value(VarType::REAL, &f))
        << "REAL bits " << std::hex << std::bit_cast<std::uint32_t>(f);
    std::uint32_t fbits = static_cast<std::uint32_t>(std::bit_cast<std::uint64_t>(d));
    float g;
    std::memcpy(&g, &fbits, sizeof g);
    ASSERT_EQ(printf_real(g, 9), format_value(VarType::REAL, &g))
        << "REAL bits " << std::hex << fbits;
    checked += 3;
  }
  EXPECT_GT(checked, 1'200'000);
  for (int i = 0; i < 50000; ++i) {
    const std::uint64_t v = next() >> (i % 64);
    const auto b = static_cast<std::uint8_t>(v);
    const auto w = static_cast<std::uint16_t>(v);
    const auto dw = static_cast<std::uint32_t>(v);
    ASSERT_EQ(printf_hex(b, 2), format_value(VarType::BYTE, &b));
    ASSERT_EQ(printf_hex(w, 4), format_value(VarType::WORD, &w));
    ASSERT_EQ(printf_hex(dw, 8), format_value(VarType::DWORD, &dw));
    ASSERT_EQ(printf_hex(v, 16), format_value(VarType::LWORD, &v));
    const auto li = static_cast<std::int64_t>(v);
    const auto si = static_cast<std::int8_t>(v);
    ASSERT_EQ(std::to_string(li), format_value(VarType::LINT, &li));
    ASSERT_EQ(std::to_string(si), format_value(VarType::SINT, &si));
    ASSERT_EQ(std::to_string(v), format_value(VarType::ULINT, &v));
  }
  // append_value() appends exactly that text.
  std::string row = "t,";
  const double d = 0.1;
  append_value(row, VarType::LREAL, &d);
  EXPECT_EQ("t,0.10000000000000001", row);
}

// IEC 61131-3 §6.3.3 literals: duration (T#), integer with base prefix,
// typed literals; and printing in IEC notation.
#include <gtest/gtest.h>

#include <limits>

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

// IEC 61131-3 §6.3.3 literals: duration (T#), integer with base prefix,
// typed literals; and printing in IEC notation.
#include <gtest/gtest.h>

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

// IEC 61131-3 §6.5.5 (2.4.1.1 in ed. 2) direct representation: %I/%Q/%M with
// size prefix X/B/W/D/L; our byte-offset addressing (see iec_address.hpp).
#include <gtest/gtest.h>

#include "plc/io/iec_address.hpp"

using namespace plc::io;

TEST(IecAddress, ParsesEverySizeAndArea) {
  struct Row {
    const char* text;
    Area area;
    AddrSize size;
    std::uint32_t byte;
    std::uint8_t bit;
  };
  const Row rows[] = {
      {"%IX0.0", Area::Input, AddrSize::Bit, 0, 0},
      {"%QX1.7", Area::Output, AddrSize::Bit, 1, 7},
      {"%I3.2", Area::Input, AddrSize::Bit, 3, 2},
      {"%IB4", Area::Input, AddrSize::Byte, 4, 0},
      {"%IW6", Area::Input, AddrSize::Word, 6, 0},
      {"%ID8", Area::Input, AddrSize::DWord, 8, 0},
      {"%IL16", Area::Input, AddrSize::LWord, 16, 0},
      {"%MW10", Area::Memory, AddrSize::Word, 10, 0},
      {"%qd100", Area::Output, AddrSize::DWord, 100, 0},
  };
  for (const Row& r : rows) {
    auto p = parse_iec_address(r.text);
    ASSERT_TRUE(p.address) << r.text << ": " << p.error;
    EXPECT_EQ(p.address->area, r.area) << r.text;
    EXPECT_EQ(p.address->size, r.size) << r.text;
    EXPECT_EQ(p.address->byte, r.byte) << r.text;
    EXPECT_EQ(p.address->bit, r.bit) << r.text;
  }
}

TEST(IecAddress, RoundTripsToCanonicalText) {
  EXPECT_EQ(parse_iec_address("%I3.2").address->to_string(), "%IX3.2");
  EXPECT_EQ(parse_iec_address("%mw10").address->to_string(), "%MW10");
  EXPECT_EQ(parse_iec_address("%QL8").address->width_bytes(), 8u);
}

TEST(IecAddress, RejectsBadAddressesWithAReason) {
  struct Row {
    const char* text;
    const char* reason;
  };
  const Row rows[] = {
      {"IX0.0", "must start with '%'"},       {"%", "missing area"},
      {"%AX0.0", "unknown area 'A'"},         {"%IZ4", "unknown size 'Z'"},
      {"%IX0.8", "out of range 0..7"},        {"%IX4", "needs a bit number"},
      {"%IW4.1", "only bit addresses"},       {"%IW", "missing byte number"},
      {"%IWx", "not a non-negative integer"}, {"%IX1.a", "not an integer"},
  };
  for (const Row& r : rows) {
    auto p = parse_iec_address(r.text);
    EXPECT_FALSE(p.address) << r.text;
    EXPECT_NE(p.error.find(r.reason), std::string::npos) << r.text << " -> " << p.error;
    EXPECT_NE(p.error.find(r.text), std::string::npos) << "error names the input: " << p.error;
  }
}

TEST(IecAddress, SizeForEachElementaryType) {
  using plc::VarType;
  EXPECT_EQ(*addr_size_for(VarType::BOOL), AddrSize::Bit);
  EXPECT_EQ(*addr_size_for(VarType::BYTE), AddrSize::Byte);
  EXPECT_EQ(*addr_size_for(VarType::INT), AddrSize::Word);
  EXPECT_EQ(*addr_size_for(VarType::REAL), AddrSize::DWord);
  EXPECT_EQ(*addr_size_for(VarType::LREAL), AddrSize::LWord);
  EXPECT_FALSE(addr_size_for(VarType::STRING));
}

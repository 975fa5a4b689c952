// F-parameter block encoding, spec nord-profisafe.md §2.2 (14 bytes).
#include <gtest/gtest.h>

#include <array>

#include "plc/fb/safety/f_parameters.hpp"

namespace {

using namespace plc::safety;

// Spec §2.2 [SPEC]: with the NORD fixed values byte 0 is 0x08 for SIL 3 and
// byte 1 is 0x48; multi-byte values big-endian; CRC1 in bytes 12-13.
TEST(SafetyFParameters, NordDefaultBlockLayout_Spec2_2) {
  FParameters p;
  p.source_add = 0x0102;
  p.dest_add = 0x0003;
  p.wd_time_ms = 150;
  p.ipar_crc = 0xA1B2C3D4;
  std::array<std::uint8_t, kFParamBlockSize> b{};
  encode(p, b);
  EXPECT_EQ(b[0], 0x08);
  EXPECT_EQ(b[1], 0x48);
  EXPECT_EQ(b[2], 0x01);
  EXPECT_EQ(b[3], 0x02);
  EXPECT_EQ(b[4], 0x00);
  EXPECT_EQ(b[5], 0x03);
  EXPECT_EQ(b[6], 0x00);
  EXPECT_EQ(b[7], 150);
  EXPECT_EQ(b[8], 0xA1);
  EXPECT_EQ(b[11], 0xD4);
  EXPECT_EQ((b[12] << 8) | b[13], p.par_crc);
  EXPECT_EQ(p.par_crc, compute_crc1(b));
}

// Self-derived: default block (source 1, dest 1, WD 100) has CRC1 0x32CB
// (see test_crc.cpp for how it was computed).
TEST(SafetyFParameters, DefaultBlockCrc1_SelfDerived_Spec2_2) {
  FParameters p;
  std::array<std::uint8_t, kFParamBlockSize> b{};
  encode(p, b);
  EXPECT_EQ(p.par_crc, 0x32CB);
  EXPECT_EQ(b[12], 0x32);
  EXPECT_EQ(b[13], 0xCB);
}

// Spec §2.2: F_SIL bits 2-3, F_CRC_Length bits 4-5, F_Par_Version bits 6-7
// of byte 1; decode() reads back what encode() wrote.
TEST(SafetyFParameters, BitFieldsRoundTrip_Spec2_2) {
  FParameters p;
  p.sil = 3;
  p.crc_length = 2;
  p.par_version = 0;
  p.block_id = 5;
  p.check_seq_nr = true;
  std::array<std::uint8_t, kFParamBlockSize> b{};
  encode(p, b);
  EXPECT_EQ(b[0], 0x01 | (3 << 2) | (2 << 4));
  EXPECT_EQ(b[1], 5 << 3);
  const FParameters q = decode(b);
  EXPECT_EQ(q.sil, 3);
  EXPECT_EQ(q.crc_length, 2);
  EXPECT_EQ(q.par_version, 0);
  EXPECT_EQ(q.block_id, 5);
  EXPECT_TRUE(q.check_seq_nr);
  EXPECT_EQ(q.par_crc, p.par_crc);
}

// A wrong CRC can be written on purpose (fault tests); CRC1 then mismatches.
TEST(SafetyFParameters, WrongCrcKeptWhenNotFilled) {
  FParameters p;
  p.par_crc = 0x1234;
  std::array<std::uint8_t, kFParamBlockSize> b{};
  encode(p, b, false);
  EXPECT_EQ(b[12], 0x12);
  EXPECT_EQ(b[13], 0x34);
  EXPECT_NE(compute_crc1(b), 0x1234);
}

}  // namespace

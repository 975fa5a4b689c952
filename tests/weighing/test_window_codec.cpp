// Window codecs against the tables of shared/specs/sartorius-pr1721.md.
#include <gtest/gtest.h>

#include <array>
#include <cstring>

#include "plc/fb/weighing/window_codec.hpp"

namespace wg = plc::weighing;
using Win = std::array<std::uint8_t, 8>;

// §4.1 DINT table: 4660 with write code 0x84: Profibus 00 00 12 34, DeviceNet 34 12 00 00.
TEST(WindowCodec, Spec41_DintExample4660BothByteOrders) {
  Win pb{}, dn{};
  wg::encode_dint(pb, 4660, wg::Bus::Profibus);
  wg::encode_dint(dn, 4660, wg::Bus::DeviceNet);
  EXPECT_EQ((Win{0x00, 0x00, 0x12, 0x34, 0, 0, 0, 0}), pb);
  EXPECT_EQ((Win{0x34, 0x12, 0x00, 0x00, 0, 0, 0, 0}), dn);
  EXPECT_EQ(4660, wg::decode_dint(pb, wg::Bus::Profibus));
  EXPECT_EQ(4660, wg::decode_dint(dn, wg::Bus::DeviceNet));
  // Bytes 4..7 are at the same place on both buses (§3): untouched.
  Win k{0, 0, 0, 0, 0xA4, 0xA5, 0xA6, 0xA7};
  wg::encode_dint(k, -1, wg::Bus::DeviceNet);
  EXPECT_EQ((Win{0xFF, 0xFF, 0xFF, 0xFF, 0xA4, 0xA5, 0xA6, 0xA7}), k);
}

// §4.1: negative values are two's complement.
TEST(WindowCodec, Spec41_DintNegativeTwosComplement) {
  Win pb{};
  wg::encode_dint(pb, -2, wg::Bus::Profibus);
  EXPECT_EQ((Win{0xFF, 0xFF, 0xFF, 0xFE, 0, 0, 0, 0}), pb);
  Win dn{};
  wg::encode_dint(dn, -123456, wg::Bus::DeviceNet);
  EXPECT_EQ(0xC0, dn[0]);  // -123456 = 0xFFFE1DC0
  EXPECT_EQ(0x1D, dn[1]);
  EXPECT_EQ(-123456, wg::decode_dint(dn, wg::Bus::DeviceNet));
}

// §4.2 REAL worked example: 200.0 = 43 48 00 00; DeviceNet reversed ([INFERRED]).
TEST(WindowCodec, Spec42_Real200BothByteOrders) {
  Win pb{}, dn{};
  wg::encode_real(pb, 200.0f, wg::Bus::Profibus);
  wg::encode_real(dn, 200.0f, wg::Bus::DeviceNet);
  EXPECT_EQ((Win{0x43, 0x48, 0x00, 0x00, 0, 0, 0, 0}), pb);
  EXPECT_EQ((Win{0x00, 0x00, 0x48, 0x43, 0, 0, 0, 0}), dn);
  EXPECT_FLOAT_EQ(200.0f, wg::decode_real(pb, wg::Bus::Profibus));
  EXPECT_FLOAT_EQ(200.0f, wg::decode_real(dn, wg::Bus::DeviceNet));
  EXPECT_FLOAT_EQ(-0.5f, [] {
    Win w{};
    wg::encode_real(w, -0.5f, wg::Bus::Profibus);
    return wg::decode_real(w, wg::Bus::Profibus);
  }());
}

// §4.3 STRING: 20 characters as 5 x 4, padded ([INFERRED] order and padding).
TEST(WindowCodec, Spec43_StringFiveChunksOfFour) {
  const char* text = "PR5510 FILLER 7";
  char back[20];
  std::memset(back, 0, sizeof back);
  for (std::size_t k = 0; k < wg::kStringChunks; ++k) {
    Win pb{};
    wg::encode_raw(pb, wg::string_chunk(text, k), wg::Bus::Profibus);
    if (k == 0) {
      EXPECT_EQ((Win{'P', 'R', '5', '5', 0, 0, 0, 0}), pb);  // reading order
    }
    Win dn{};
    wg::encode_raw(dn, wg::string_chunk(text, k), wg::Bus::DeviceNet);
    if (k == 0) {
      EXPECT_EQ((Win{'5', '5', 'R', 'P', 0, 0, 0, 0}), dn);  // reversed
    }
    wg::put_string_chunk(back, k, wg::decode_raw(dn, wg::Bus::DeviceNet));
  }
  EXPECT_EQ(' ', back[19]);  // padding
  EXPECT_EQ(std::string_view("PR5510 FILLER 7"), wg::trim_string(back));
  // Longer than 20: cut at 20.
  EXPECT_EQ(wg::string_chunk("ABCDEFGHIJKLMNOPQRSTUVWXYZ", 4), wg::string_chunk("QRST", 0));
}

// §5.3 code 4: decimals 02, unit kg 03, d 50 = 32h, last error 35 = 23h.
TEST(WindowCodec, Spec53_Code4PackedFormatMsbFirst) {
  const wg::FormatInfo f{2, static_cast<std::uint8_t>(wg::Unit::kg), 50, 35};
  const std::uint32_t v = wg::pack_format(f);
  EXPECT_EQ(0x02033223u, v);
  Win pb{}, dn{};
  wg::encode_raw(pb, v, wg::Bus::Profibus);
  wg::encode_raw(dn, v, wg::Bus::DeviceNet);
  EXPECT_EQ((Win{0x02, 0x03, 0x32, 0x23, 0, 0, 0, 0}), pb);  // R[0] = decimals
  EXPECT_EQ((Win{0x23, 0x32, 0x03, 0x02, 0, 0, 0, 0}), dn);
  EXPECT_EQ(f, wg::unpack_format(wg::decode_raw(dn, wg::Bus::DeviceNet)));
}

// §5.3 [AMBIG] 9: the CC-Link word order alternative, configurable.
TEST(WindowCodec, Spec53_Code4PackedFormatCcLinkWordOrder) {
  const wg::FormatInfo f{3, static_cast<std::uint8_t>(wg::Unit::lb), 5, 47};
  const std::uint32_t v = wg::pack_format(f, wg::PackedOrder::CcLink);
  EXPECT_EQ(0x052F0305u, v);  // (RWrn1 << 16) | RWrn0
  EXPECT_EQ(f, wg::unpack_format(v, wg::PackedOrder::CcLink));
  EXPECT_NE(f, wg::unpack_format(v, wg::PackedOrder::MsbFirst));
}

// §5.3 code 5: PR5510 -> 55h 10h; Rel 3.00 -> 03h 00h.
TEST(WindowCodec, Spec53_Code5ModelAndVersion) {
  const std::uint32_t v = wg::pack_model({0x5510, 0x0300});
  Win pb{};
  wg::encode_raw(pb, v, wg::Bus::Profibus);
  EXPECT_EQ((Win{0x55, 0x10, 0x03, 0x00, 0, 0, 0, 0}), pb);
  EXPECT_EQ((wg::ModelInfo{0x5510, 0x0300}), wg::unpack_model(v));
}

// §3.4 read bytes 5, 6, 7: each of the 24 bits at its table position.
TEST(WindowCodec, Spec34_AllTwentyFourStatusBitsNamed) {
  struct Case {
    std::size_t byte;
    unsigned bit;
    bool wg::StatusBits::*field;
  };
  const Case cases[] = {
      {5, 0, &wg::StatusBits::Limit1},     {5, 1, &wg::StatusBits::Limit2},
      {5, 2, &wg::StatusBits::Limit3},     {5, 3, &wg::StatusBits::Out1},
      {5, 4, &wg::StatusBits::Out2},       {5, 5, &wg::StatusBits::Out3},
      {5, 6, &wg::StatusBits::PowerFail},  {5, 7, &wg::StatusBits::WriteActive},
      {6, 0, &wg::StatusBits::TestActive}, {6, 1, &wg::StatusBits::CalChanged},
      {6, 2, &wg::StatusBits::TareActive}, {6, 3, &wg::StatusBits::Inp1},
      {6, 4, &wg::StatusBits::Inp2},       {6, 5, &wg::StatusBits::Inp3},
      {6, 6, &wg::StatusBits::CmdError},   {6, 7, &wg::StatusBits::CmdBusy},
      {7, 0, &wg::StatusBits::AduError},   {7, 1, &wg::StatusBits::AboveFsd},
      {7, 2, &wg::StatusBits::Overload},   {7, 3, &wg::StatusBits::BelowZero},
      {7, 4, &wg::StatusBits::CenterZero}, {7, 5, &wg::StatusBits::InsideZsr},
      {7, 6, &wg::StatusBits::StandStill}, {7, 7, &wg::StatusBits::Dimmed},
  };
  for (const Case& c : cases) {
    Win r{};
    r[c.byte] = static_cast<std::uint8_t>(1U << c.bit);
    const wg::StatusBits s = wg::decode_status(r);
    wg::StatusBits expect{};
    expect.*c.field = true;
    EXPECT_EQ(expect, s) << "R[" << c.byte << "]." << c.bit;
    Win back{};
    wg::encode_status(s, back);
    EXPECT_EQ(r, back) << "R[" << c.byte << "]." << c.bit;
  }
}

// §3.3 write bytes 6/7 and §5.4 write codes, §5.2 read codes: the values.
TEST(WindowCodec, Spec33_54_52_CodeAndBitValues) {
  EXPECT_EQ(0, static_cast<int>(wg::CommandBit::SetZero));
  EXPECT_EQ(1, static_cast<int>(wg::CommandBit::SetTare));
  EXPECT_EQ(2, static_cast<int>(wg::CommandBit::ResTare));
  EXPECT_EQ(3, static_cast<int>(wg::CommandBit::SetTest));
  EXPECT_EQ(4, static_cast<int>(wg::CommandBit::ResTest));
  EXPECT_EQ(5, static_cast<int>(wg::CommandBit::ResPower));
  EXPECT_EQ(0x70, static_cast<int>(wg::WriteCode::SetZero));
  EXPECT_EQ(0x71, static_cast<int>(wg::WriteCode::SetTare));
  EXPECT_EQ(0x72, static_cast<int>(wg::WriteCode::ResetTare));
  EXPECT_EQ(0x73, static_cast<int>(wg::WriteCode::StartTest));
  EXPECT_EQ(0x74, static_cast<int>(wg::WriteCode::EndTest));
  EXPECT_EQ(0x75, static_cast<int>(wg::WriteCode::ResetPowerFail));
  EXPECT_EQ(0x08, static_cast<int>(wg::ReadCode::Gross));
  EXPECT_EQ(0x09, static_cast<int>(wg::ReadCode::Net));
  EXPECT_EQ(0x0A, static_cast<int>(wg::ReadCode::Tare));
  EXPECT_EQ(0x0C, static_cast<int>(wg::ReadCode::Gross100));
  EXPECT_EQ(0x0E, static_cast<int>(wg::ReadCode::FullScale));
  // §5.1 code ranges.
  EXPECT_FALSE(wg::is_defined_write_code(0x00));
  EXPECT_FALSE(wg::is_defined_write_code(0x0F));
  EXPECT_TRUE(wg::is_defined_write_code(0x18));
  EXPECT_TRUE(wg::is_defined_write_code(0x39));
  EXPECT_FALSE(wg::is_defined_write_code(0x3A));
  EXPECT_FALSE(wg::is_defined_write_code(0x76));
  EXPECT_TRUE(wg::is_defined_write_code(0x84));
  EXPECT_TRUE(wg::is_defined_write_code(0xC7));
  EXPECT_FALSE(wg::is_defined_write_code(0xC8));
  EXPECT_FALSE(wg::is_defined_read_code(0x03));
  EXPECT_FALSE(wg::is_defined_read_code(0x06));
  EXPECT_FALSE(wg::is_defined_read_code(0x0F));
  EXPECT_TRUE(wg::is_defined_read_code(0x18));
  EXPECT_FALSE(wg::is_defined_read_code(0xC8));
}

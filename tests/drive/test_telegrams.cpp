// Telegram types, words, scaling and parameter-channel encoding against the
// tables of shared/specs/hiwin-e1-profinet.md (each test names its table).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "plc/fb/drive/parameter_channel.hpp"
#include "plc/fb/drive/scaling.hpp"
#include "plc/fb/drive/sign_of_life.hpp"
#include "plc/fb/drive/telegrams.hpp"

namespace plc::drive {

TEST(Table3_2_1, TelegramSizesInWords) {
  EXPECT_EQ(Telegram3Out::kWords, 5u);
  EXPECT_EQ(Telegram3In::kWords, 9u);
  EXPECT_EQ(Telegram9Out::kWords, 10u);
  EXPECT_EQ(Telegram9In::kWords, 5u);
  EXPECT_EQ(Telegram111Out::kWords, 12u);
  EXPECT_EQ(Telegram111In::kWords, 12u);
  EXPECT_EQ(out_bytes(TelegramType::Standard3), 10u);
  EXPECT_EQ(in_bytes(TelegramType::Standard3), 18u);
  EXPECT_EQ(out_bytes(TelegramType::Standard9), 20u);
  EXPECT_EQ(in_bytes(TelegramType::Standard9), 10u);
  EXPECT_EQ(out_bytes(TelegramType::Hiwin111), 24u);
  EXPECT_EQ(in_bytes(TelegramType::Hiwin111), 24u);
}

TEST(Table3_2_2, Telegram111WordOrderBigEndian) {
  Telegram111Out o;
  o.stw1 = Stw1Pos::from(0x043F);
  o.pos_stw1 = PosStw1::from(0x8100);
  o.pos_stw2 = PosStw2::from(0x0002);
  o.stw2 = Stw2::from(0x5000);
  o.override_ = 0x4000;
  o.mdi_tarpos = 0x12345678;
  o.mdi_velocity = 0x0A0B0C0D;
  o.mdi_acc = 0x2000;
  o.mdi_dec = 0x1000;
  std::array<std::uint8_t, 24> b{};
  b.fill(0xEE);
  o.encode(b);
  const std::array<std::uint8_t, 24> want{0x04, 0x3F, 0x81, 0x00, 0x00, 0x02, 0x50, 0x00,
                                          0x40, 0x00, 0x12, 0x34, 0x56, 0x78, 0x0A, 0x0B,
                                          0x0C, 0x0D, 0x20, 0x00, 0x10, 0x00, 0x00, 0x00};
  EXPECT_EQ(b, want);  // PZD12 reserved: sent as 0
  const auto d = Telegram111Out::decode(b);
  EXPECT_EQ(d.mdi_tarpos, 0x12345678);
  EXPECT_EQ(d.stw1.word(), 0x043F);

  Telegram111In i;
  i.zsw1 = Zsw1Pos::from(0x2737);
  i.xist_a = -2;
  i.nist_b = 0x40000000;
  i.fault_code = 0x0710;
  i.warn_code = 0x09A0;
  i.meldw = Meldw::from(0x39C2);
  std::array<std::uint8_t, 24> r{};
  i.encode(r);
  EXPECT_EQ(r[0], 0x27);
  EXPECT_EQ(r[1], 0x37);
  EXPECT_EQ(r[8], 0x39);
  EXPECT_EQ(r[9], 0xC2);
  EXPECT_EQ(r[10], 0xFF);
  EXPECT_EQ(r[13], 0xFE);
  EXPECT_EQ(r[14], 0x40);
  EXPECT_EQ(r[18], 0x07);
  EXPECT_EQ(r[19], 0x10);
  EXPECT_EQ(r[20], 0x09);
  EXPECT_EQ(r[21], 0xA0);
  EXPECT_EQ(Telegram111In::kXistA, 10u);
  EXPECT_EQ(Telegram111In::kNistB, 14u);
  EXPECT_EQ(Telegram111In::kFaultCode, 18u);
  EXPECT_EQ(Telegram111In::kWarnCode, 20u);
}

TEST(Table3_2_2, Telegram9And3Offsets) {
  EXPECT_EQ(Telegram9Out::kSatzanw, 2u);
  EXPECT_EQ(Telegram9Out::kStw2, 4u);
  EXPECT_EQ(Telegram9Out::kMdiTarpos, 6u);
  EXPECT_EQ(Telegram9Out::kMdiVelocity, 10u);
  EXPECT_EQ(Telegram9Out::kMdiAcc, 14u);
  EXPECT_EQ(Telegram9Out::kMdiDec, 16u);
  EXPECT_EQ(Telegram9Out::kMdiMode, 18u);
  EXPECT_EQ(Telegram9In::kAktsatz, 2u);
  EXPECT_EQ(Telegram9In::kXistA, 6u);
  EXPECT_EQ(Telegram3Out::kNsollB, 2u);
  EXPECT_EQ(Telegram3Out::kStw2, 6u);
  EXPECT_EQ(Telegram3Out::kG1Stw, 8u);
  EXPECT_EQ(Telegram3In::kG1Xist1, 10u);
  EXPECT_EQ(Telegram3In::kG1Xist2, 14u);
  Telegram9Out o;
  o.mdi_mode.absolute = true;
  o.satzanw.activate_mdi = true;
  o.mdi_tarpos = -1;
  std::array<std::uint8_t, 20> b{};
  o.encode(b);
  EXPECT_EQ(b[2], 0x80);
  EXPECT_EQ(b[6], 0xFF);
  EXPECT_EQ(b[9], 0xFF);
  EXPECT_EQ(b[19], 0x01);
  Telegram3In t;
  t.g1_xist1 = 0x01020304;
  std::array<std::uint8_t, 18> c{};
  t.encode(c);
  EXPECT_EQ(c[10], 0x01);
  EXPECT_EQ(c[13], 0x04);
}

// Tables 3.3.1.1 and 3.3.2.1: STW1 bits.
TEST(Table3_3_2_1, Stw1PositioningBits) {
  EXPECT_EQ(Stw1Pos::kOn, 1u << 0);
  EXPECT_EQ(Stw1Pos::kNoCoastStop, 1u << 1);
  EXPECT_EQ(Stw1Pos::kNoQuickStop, 1u << 2);
  EXPECT_EQ(Stw1Pos::kEnableOperation, 1u << 3);
  EXPECT_EQ(Stw1Pos::kNoRejectTask, 1u << 4);
  EXPECT_EQ(Stw1Pos::kNoIntermediateStop, 1u << 5);
  EXPECT_EQ(Stw1Pos::kActivateTask, 1u << 6);
  EXPECT_EQ(Stw1Pos::kFaultAck, 1u << 7);
  EXPECT_EQ(Stw1Pos::kJog1, 1u << 8);
  EXPECT_EQ(Stw1Pos::kJog2, 1u << 9);
  EXPECT_EQ(Stw1Pos::kControlByPlc, 1u << 10);
  EXPECT_EQ(Stw1Pos::kStartHoming, 1u << 11);
  for (unsigned b = 0; b < 16; ++b) {
    const auto w = static_cast<std::uint16_t>(1u << b);
    EXPECT_EQ(Stw1Pos::from(w).word(), b < 12 ? w : 0) << b;  // 12-15 reserved
  }
  const auto s = Stw1Pos::from(0x043F);
  EXPECT_TRUE(s.on && s.no_coast_stop && s.no_quick_stop && s.enable_operation &&
              s.no_reject_task && s.no_intermediate_stop && s.control_by_plc);
  EXPECT_FALSE(s.activate_task || s.fault_ack || s.jog1 || s.jog2 || s.start_homing);
}

TEST(Table3_3_1_1, Stw1SpeedBitsReservedDropped) {
  EXPECT_EQ(Stw1Speed::from(0x047F).word(), 0x040F);  // bits 4-6 reserved in telegram 3
  EXPECT_EQ(Stw1Speed::from(0x04FE).word(), 0x048E);
  EXPECT_TRUE(Stw1Speed::from(0x0480).fault_ack);
}

TEST(Table3_4_1, Stw2SignOfLife) {
  EXPECT_EQ(Stw2::from(0xF123).controller_sign_of_life, 15);
  EXPECT_EQ(Stw2{7}.word(), 0x7000);
  EXPECT_EQ(Stw2::from(0x0FFF).word(), 0);  // bits 0-11 reserved
}

TEST(Table3_5_x, Zsw1Bits) {
  EXPECT_EQ(Zsw1Pos::kFollowingErrorInTolerance, 1u << 8);
  EXPECT_EQ(Zsw1Pos::kControlRequested, 1u << 9);
  EXPECT_EQ(Zsw1Pos::kTargetReached, 1u << 10);
  EXPECT_EQ(Zsw1Pos::kHomePositionSet, 1u << 11);
  EXPECT_EQ(Zsw1Pos::kTaskAck, 1u << 12);
  EXPECT_EQ(Zsw1Pos::kMotorStopped, 1u << 13);
  EXPECT_EQ(Zsw1Speed::kSpeedErrorInTolerance, 1u << 8);
  EXPECT_EQ(Zsw1Speed::kSpeedReached, 1u << 10);
  for (unsigned b = 0; b < 16; ++b) {
    const auto w = static_cast<std::uint16_t>(1u << b);
    EXPECT_EQ(Zsw1Pos::from(w).word(), b < 14 ? w : 0) << b;
    EXPECT_EQ(Zsw1Speed::from(w).word(), b < 11 ? w : 0) << b;
  }
  const auto z = Zsw1Speed::from(0x0237);
  EXPECT_TRUE(z.ready_to_switch_on && z.ready_to_operate && z.operation_enabled &&
              z.no_coast_stop && z.no_quick_stop && z.control_requested);
  EXPECT_FALSE(z.fault || z.switch_on_inhibited || z.warning);
}

TEST(Table3_6_x, Zsw2PulsesAndSignOfLife) {
  const auto z = Zsw2::from(0x3800);
  EXPECT_TRUE(z.pulses_enabled);
  EXPECT_EQ(z.drive_sign_of_life, 3);
  EXPECT_FALSE(Zsw2::from(0x3800, false).pulses_enabled);  // telegram 3: bit 11 reserved
}

TEST(Table3_7_1and3_8_1, EncoderWords) {
  const auto g = G1Stw::from(0xC025);
  EXPECT_TRUE(g.function1 && g.function3 && g.activate_parking && g.ack_sensor_error);
  EXPECT_EQ(g.command, static_cast<std::uint8_t>(G1Command::ReadValue));
  EXPECT_EQ(g.word(), 0xC025);
  const auto z = G1Zsw::from(0xC8FF);
  EXPECT_TRUE(z.function4_active && z.value4_available && z.error_ack_in_process &&
              z.parking_active && z.sensor_error);
  EXPECT_EQ(G1Zsw::from(0x3700).word(), 0);  // 8-10, 12-13 reserved
}

TEST(Tables3_9_to_3_16, PositioningWords) {
  EXPECT_EQ(Satzanw::from(0xFFFF).word(), 0x8000);
  EXPECT_EQ(Aktsatz::from(0xFFFF).word(), 0x8000);
  EXPECT_EQ(MdiMode::from(0xFFFF).word(), 0x0001);
  EXPECT_EQ(PosStw1::from(0xFFFF).word(), 0x8100);
  EXPECT_EQ(PosStw2::from(0xFFFF).word(), 0x0002);
  EXPECT_EQ(PosZsw1::from(0xFFFF).word(), 0x8F00);
  EXPECT_EQ(PosZsw2::from(0xFFFF).word(), 0x8034);
  EXPECT_EQ(Meldw::from(0xFFFF).word(), 0x39C2);
  const auto p = PosZsw1::from(0x0C00);
  EXPECT_TRUE(p.jog_active && p.homing_active);
  EXPECT_FALSE(p.mdi_active);
  const auto m = Meldw::from(1u << 13);
  EXPECT_TRUE(m.pulses_enabled);
}

// Table 3.1.1 and §7.1: NSOLL_B/NIST_B, MDI_VELOCITY, MDI_ACC/DEC, OVERRIDE.
TEST(Table3_1_1, Scaling) {
  EXPECT_EQ(to_nsoll_b(3000, 3000), 0x40000000);
  EXPECT_EQ(to_nsoll_b(1500, 3000), 0x20000000);
  EXPECT_EQ(to_nsoll_b(-3000, 3000), -0x40000000);
  EXPECT_EQ(speed_to_nsoll_b(9000, 3000), 0x7FFFFFFF);  // an actual value saturates
  EXPECT_DOUBLE_EQ(nist_b_to_speed(0x20000000, 3000), 1500);
  EXPECT_EQ(to_mdi_velocity(1000.0 / 60.0), 1);  // 1 = 1000 CU/min
  EXPECT_EQ(cu_per_s_to_mdi_velocity(-5), 0);    // an actual value: magnitude only
  EXPECT_EQ(to_mdi_acc(100), 0x4000);
  EXPECT_EQ(to_override(100), 0x4000);
  EXPECT_EQ(to_mdi_tarpos(-20000.4), -20000);
  EXPECT_NEAR(override_to_percent(32767), 199.99, 0.01);
}

// Table 3.1.1 "Valid range" column: a setpoint whose wire value falls outside
// its field, or that is not a number, is refused (nullopt), never wrapped or
// clamped. The edges of each range are accepted exactly.
TEST(Table3_1_1, SetpointOutsideItsFieldIsRefused) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  // MDI_TARPOS Int32 -2^31 .. 2^31-1 (1 = 1 CU).
  EXPECT_EQ(to_mdi_tarpos(2147483647.0), 2147483647);
  EXPECT_EQ(to_mdi_tarpos(-2147483648.0), std::numeric_limits<std::int32_t>::min());
  EXPECT_FALSE(to_mdi_tarpos(2147483648.0));
  EXPECT_FALSE(to_mdi_tarpos(3e9));  // would wrap to -1294967296
  EXPECT_FALSE(to_mdi_tarpos(-2147483649.0));
  EXPECT_FALSE(to_mdi_tarpos(nan));
  EXPECT_FALSE(to_mdi_tarpos(inf));
  EXPECT_FALSE(to_mdi_tarpos(-inf));
  // MDI_VELOCITY 0 .. 2^31-1 (1 = 1000 CU/min).
  const double vmax = 2147483647.0 * 1000.0 / 60.0;
  EXPECT_EQ(to_mdi_velocity(vmax), 2147483647);
  EXPECT_FALSE(to_mdi_velocity(vmax + 100.0));
  EXPECT_FALSE(to_mdi_velocity(-1000.0));
  EXPECT_FALSE(to_mdi_velocity(nan));
  EXPECT_FALSE(to_mdi_velocity(inf));
  // MDI_ACC / MDI_DEC 0 .. 16384 (0x4000 = 100 %).
  EXPECT_EQ(to_mdi_acc(0), 0);
  EXPECT_EQ(to_mdi_acc(100), 16384);
  EXPECT_FALSE(to_mdi_acc(100.01));
  EXPECT_FALSE(to_mdi_acc(150));
  EXPECT_FALSE(to_mdi_acc(-1));
  EXPECT_FALSE(to_mdi_acc(nan));
  // OVERRIDE 0 .. 32767 (0x4000 = 100 %, so ~199.99 %).
  EXPECT_EQ(to_override(199), 32604);
  EXPECT_FALSE(to_override(200));
  EXPECT_FALSE(to_override(250));
  EXPECT_FALSE(to_override(-1));
  EXPECT_FALSE(to_override(inf));
  // NSOLL_B Int32 (0x40000000 = 100 % of the reference).
  EXPECT_EQ(to_nsoll_b(5999.99, 3000), 2147480069);
  EXPECT_FALSE(to_nsoll_b(6000, 3000));  // 2^31: one past the top
  EXPECT_EQ(to_nsoll_b(-6000, 3000), std::numeric_limits<std::int32_t>::min());
  EXPECT_FALSE(to_nsoll_b(9000, 3000));
  EXPECT_FALSE(to_nsoll_b(1500, 0));
  EXPECT_FALSE(to_nsoll_b(1500, -3000));
  EXPECT_FALSE(to_nsoll_b(nan, 3000));
  EXPECT_FALSE(to_nsoll_b(1500, nan));
  EXPECT_FALSE(to_nsoll_b(1500, inf));
}

// The actual values (NIST_B, XIST_A) are rounded half away from zero as
// std::llround does (Table 3.1.1 gives no rounding; the drive model and the
// golden traces rest on llround): the inline rounding must agree for every
// double, halves, their neighbours, the 2^52 edge and beyond.
TEST(Table3_1_1, InlineRoundingIsLlround) {
  std::vector<double> v = {0.0,
                           -0.0,
                           0.5,
                           -0.5,
                           1.5,
                           -1.5,
                           2.5,
                           -2.5,
                           1e-300,
                           0.49999999999999994,
                           -0.49999999999999994,
                           4503599627370495.5,
                           -4503599627370495.5,
                           4503599627370496.0,
                           9007199254740993.0,
                           -9007199254740993.0,
                           2147483647.5,
                           -2147483648.5,
                           1e18,
                           -1e18};
  for (double x : {0.5, 1.5, 2.5, 1234.5, -1234.5, 4503599627370495.5}) {
    v.push_back(std::nextafter(x, 0.0));
    v.push_back(std::nextafter(x, 1e300));
  }
  std::uint64_t s = 0x9E3779B97F4A7C15ULL;
  for (int i = 0; i < 100000; ++i) {
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    const double m = static_cast<double>(s >> 11) / 9007199254740992.0;  // [0, 1)
    const int e = static_cast<int>(s % 64) - 8;
    v.push_back(std::ldexp(m, e) * ((s >> 10) & 1 ? -1 : 1));
    v.push_back(std::ldexp(std::floor(std::ldexp(m, 20)) + 0.5, e - 20));  // a half
  }
  for (double x : v) ASSERT_EQ(detail::llround_inline(x), std::llround(x)) << x;
}

TEST(SignOfLife, CountsOneToFifteenSkippingZero) {
  EXPECT_EQ(next_sign_of_life(0), 1);
  EXPECT_EQ(next_sign_of_life(14), 15);
  EXPECT_EQ(next_sign_of_life(15), 1);
  SignOfLifeMonitor m;
  EXPECT_TRUE(m.update(0, 2));  // not started while 0
  std::uint8_t v = 0;
  for (int i = 0; i < 40; ++i) EXPECT_TRUE(m.update(v = next_sign_of_life(v), 2));
  EXPECT_TRUE(m.update(v, 2));
  EXPECT_TRUE(m.update(v, 2));
  EXPECT_FALSE(m.update(v, 2));  // third consecutive failure > tolerance 2
}

// §6.2: Pt/Ut numbers read as hex.
TEST(Table4_2_1, PtUtToPnu) {
  EXPECT_EQ(pt_pnu(0x317), 0x2317);
  EXPECT_EQ(pt_pnu(0x317), 8983);
  EXPECT_EQ(pt_pnu(0x53A), 0x253A);
  EXPECT_EQ(pt_pnu(0x30A), 0x230A);
  EXPECT_EQ(ut_pnu(0x095), 0x4095);
  EXPECT_EQ(parse_pnu("Pt317"), 0x2317);
  EXPECT_EQ(parse_pnu("pt53a"), 0x253A);
  EXPECT_EQ(parse_pnu("Ut095"), 0x4095);
  EXPECT_EQ(parse_pnu("16#3200"), 0x3200);
  EXPECT_EQ(parse_pnu("0x3215"), 0x3215);
  EXPECT_EQ(parse_pnu("945"), 945);
  EXPECT_EQ(parse_pnu("Pt31G"), 0xFFFF);
}

// Tables 4.3.1.1 and 4.3.2.1: request layouts.
TEST(Table4_3_1_1, ReadRequestBytes) {
  ParamRequest r;
  r.reference = 0x11;
  r.request_id = 0x01;
  r.pnu = 0x2317;
  std::array<std::uint8_t, 240> b{};
  ASSERT_EQ(r.encode(b), 10u);
  const std::vector<std::uint8_t> want{0x11, 0x01, 0x00, 0x01, 0x10, 0x00, 0x23, 0x17, 0x00, 0x00};
  EXPECT_EQ(std::vector<std::uint8_t>(b.begin(), b.begin() + 10), want);
}

TEST(Table4_3_2_1, WriteRequestBytes) {
  ParamRequest r;
  r.reference = 0x22;
  r.request_id = 0x02;
  r.pnu = 0x3200;
  r.format = 0x04;
  r.num_values = 1;
  r.values[0] = 1;
  std::array<std::uint8_t, 240> b{};
  ASSERT_EQ(r.encode(b), 16u);
  const std::vector<std::uint8_t> want{0x22, 0x02, 0x00, 0x01, 0x10, 0x00, 0x32, 0x00,
                                       0x00, 0x00, 0x04, 0x01, 0x00, 0x00, 0x00, 0x01};
  EXPECT_EQ(std::vector<std::uint8_t>(b.begin(), b.begin() + 16), want);
  ParamRequest d;
  ASSERT_EQ(decode_request({b.data(), 16}, d), ParseResult::Ok);
  EXPECT_EQ(d.pnu, 0x3200);
  EXPECT_EQ(d.values[0], 1u);
}

// Tables 4.3.1.2/4.3.1.3/4.3.2.2/4.3.3.2: responses.
TEST(Table4_3_x, Responses) {
  ParamResponse p;
  p.reference = 5;
  p.response_id = 0x01;
  p.format = 0x06;
  p.num_values = 1;
  p.values[0] = 3000;
  std::array<std::uint8_t, 240> b{};
  ASSERT_EQ(p.encode(b), 8u);
  EXPECT_EQ(b[4], 0x06);
  EXPECT_EQ(b[6], 0x0B);
  EXPECT_EQ(b[7], 0xB8);
  ParamResponse n;
  n.reference = 5;
  n.response_id = 0x81;
  n.format = 0x44;
  n.num_values = 1;
  n.error_no = 0x14;
  ASSERT_EQ(n.encode(b), 8u);
  ParamResponse d;
  ASSERT_TRUE(decode_response({b.data(), 8}, d));
  EXPECT_TRUE(d.negative());
  EXPECT_EQ(d.error_no, 0x14);
  ParamResponse w;
  w.reference = 7;
  w.response_id = 0x02;
  EXPECT_EQ(w.encode(b), 4u);  // Table 4.3.2.2: 4 bytes only
  ParamResponse a;             // Table 4.3.3.2: n values
  a.response_id = 0x01;
  a.format = 0x06;
  a.num_values = 3;
  a.values = {1, 2, 3};
  EXPECT_EQ(a.encode(b), 12u);
  ParamResponse by;  // 1-byte values padded to a word
  by.response_id = 0x01;
  by.format = 0x05;
  by.num_values = 1;
  by.values[0] = 9;
  EXPECT_EQ(by.encode(b), 8u);
}

TEST(Table4_3_5_1, FormatCodes) {
  EXPECT_EQ(format_size(0x01), 1u);
  EXPECT_EQ(format_size(0x02), 1u);
  EXPECT_EQ(format_size(0x03), 2u);
  EXPECT_EQ(format_size(0x04), 4u);
  EXPECT_EQ(format_size(0x05), 1u);
  EXPECT_EQ(format_size(0x06), 2u);
  EXPECT_EQ(format_size(0x07), 4u);
  EXPECT_EQ(format_size(0x08), 4u);
  EXPECT_EQ(format_size(0x41), 1u);
  EXPECT_EQ(format_size(0x42), 2u);
  EXPECT_EQ(format_size(0x43), 4u);
  EXPECT_EQ(format_size(0x44), 0u);
  EXPECT_EQ(format_size(0x00), 0u);
  EXPECT_STREQ(format_name(0x08), "Float32");
  EXPECT_DOUBLE_EQ(raw_to_double(0xFFFF, 0x03), -1);
  EXPECT_DOUBLE_EQ(raw_to_double(double_to_raw(1.5, 0x08), 0x08), 1.5);
}

// Table 4.3.5.1: the range of each value format; a write value outside it
// (or not a number) does not fit and must not be sent (it would wrap).
TEST(Table4_3_5_1, ValueFitsFormatRange) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(value_fits_format(1, 0x01));
  EXPECT_FALSE(value_fits_format(2, 0x01));
  EXPECT_TRUE(value_fits_format(-128, 0x02));
  EXPECT_FALSE(value_fits_format(128, 0x02));
  EXPECT_TRUE(value_fits_format(-32768, 0x03));
  EXPECT_FALSE(value_fits_format(40000, 0x03));
  EXPECT_TRUE(value_fits_format(-2147483648.0, 0x04));
  EXPECT_FALSE(value_fits_format(3e9, 0x04));
  EXPECT_TRUE(value_fits_format(255, 0x05));
  EXPECT_FALSE(value_fits_format(-1, 0x05));
  EXPECT_TRUE(value_fits_format(65535, 0x06));
  EXPECT_FALSE(value_fits_format(65536, 0x06));
  EXPECT_FALSE(value_fits_format(-1, 0x06));  // would go out as 65535
  EXPECT_TRUE(value_fits_format(4294967295.0, 0x07));
  EXPECT_FALSE(value_fits_format(4294967296.0, 0x07));
  EXPECT_TRUE(value_fits_format(255, 0x41));
  EXPECT_FALSE(value_fits_format(256, 0x41));
  EXPECT_TRUE(value_fits_format(65535, 0x42));
  EXPECT_FALSE(value_fits_format(70000, 0x42));
  EXPECT_TRUE(value_fits_format(4294967295.0, 0x43));
  EXPECT_FALSE(value_fits_format(-1, 0x43));
  EXPECT_FALSE(value_fits_format(-3.5e38, 0x08));
  EXPECT_TRUE(value_fits_format(3.4e38, 0x08));
  EXPECT_TRUE(value_fits_format(0.25, 0x08));
  for (std::uint8_t f : {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x41, 0x42, 0x43}) {
    EXPECT_FALSE(value_fits_format(nan, f)) << int(f);
    EXPECT_FALSE(value_fits_format(inf, f)) << int(f);
    EXPECT_FALSE(value_fits_format(-inf, f)) << int(f);
  }
  EXPECT_FALSE(value_fits_format(0, 0x44));  // Error is not a value format
}

TEST(Table4_3_6_1, ErrorNames) {
  EXPECT_STREQ(param_error_text(0x00), "Impermissible parameter number");
  EXPECT_STREQ(param_error_text(0x11), "Request cannot be executed because of operating state");
  EXPECT_STREQ(param_error_text(0x23), "Multi-parameter access not supported");
  EXPECT_STREQ(param_error_text(0x0D), "reserved");
  for (int e : {0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x09, 0x0B, 0x0F,
                0x11, 0x14, 0x15, 0x16, 0x17, 0x18, 0x19, 0x20, 0x21, 0x22, 0x23})
    EXPECT_STRNE(param_error_text(static_cast<std::uint16_t>(e)), "reserved") << e;
}

}  // namespace plc::drive

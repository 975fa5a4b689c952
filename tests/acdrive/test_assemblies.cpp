// The assembly codecs against the byte layouts of toyo-vf66-devicenet.md §7
// (the manual's Tables 3.7.1, 3.7.2, 6.2, 6.3, 6.5, 6.5.1), written out as
// literal bytes here: the device model shares these codecs, so only the
// tables can catch a codec mistake. Also §2's reserved-bit rule, §6.1's
// worked scaling examples and Table 6.4's codes.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "plc/fb/acdrive/assemblies.hpp"
#include "plc/fb/acdrive/protect_codes.hpp"
#include "plc/fb/acdrive/speed_scale.hpp"

namespace plc::acdrive {

namespace {
using Bytes = std::vector<std::uint8_t>;
template <class T>
Bytes enc(const T& v, std::size_t n) {
  Bytes b(n, 0xAA);
  EXPECT_TRUE(encode(v, b));
  return b;
}
}  // namespace

TEST(AcdriveAssemblies, InstanceSelectionAndSizes_Table4_4_Table6_1) {
  EXPECT_EQ(output_instance(0), 20);
  EXPECT_EQ(output_instance(1), 21);
  EXPECT_EQ(output_instance(2), 100);
  EXPECT_EQ(output_instance(10), 108);
  EXPECT_EQ(output_instance(11), 0);
  EXPECT_EQ(input_instance(0), 70);
  EXPECT_EQ(input_instance(1), 71);
  EXPECT_EQ(input_instance(2), 120);
  EXPECT_EQ(input_instance(14), 132);
  EXPECT_EQ(input_instance(15), 140);
  EXPECT_EQ(input_instance(16), 0);
  // Words per instance, Table 6.1: 100 = 4 words ... 108 = 12 words.
  const std::array<std::size_t, 9> out_words = {4, 5, 6, 7, 8, 9, 10, 11, 12};
  for (unsigned i = 0; i < 9; ++i) EXPECT_EQ(output_size(100 + i), 2 * out_words[i]);
  // 120 = 6 words ... 132 = 18 words; 140 = 4 words.
  for (unsigned i = 0; i < 13; ++i) EXPECT_EQ(input_size(120 + i), 2 * (6 + i));
  EXPECT_EQ(input_size(140), 8u);
  EXPECT_EQ(output_size(20), 4u);
  EXPECT_EQ(input_size(71), 4u);
  EXPECT_EQ(output_size(99), 0u);
  EXPECT_EQ(input_size(133), 0u);
}

TEST(AcdriveAssemblies, Output20_Table3_7_1) {
  // Run Fwd b0, Fault Reset b2; SpeedRef 4567 = 0x11D7 little-endian.
  EXPECT_EQ(enc(Output20{true, true, 4567}, 4), (Bytes{0x05, 0x00, 0xD7, 0x11}));
  EXPECT_EQ(enc(Output20{true, false, -1}, 4), (Bytes{0x01, 0x00, 0xFF, 0xFF}));
  // §2: the receiver ignores reserved bits (byte 0 b1, b3..b7; byte 1).
  Output20 o;
  ASSERT_TRUE(decode(Bytes{0xFA, 0xFF, 0x00, 0x80}, o));
  EXPECT_FALSE(o.run_fwd);
  EXPECT_FALSE(o.fault_reset);
  EXPECT_EQ(o.speed_ref, -32768);
  EXPECT_FALSE(decode(Bytes{0x01, 0x00, 0x00}, o)) << "wrong length";
}

TEST(AcdriveAssemblies, Output21_Table3_7_1) {
  Output21 all{true, true, true, true, true, 0x1234};
  EXPECT_EQ(enc(all, 4), (Bytes{0x67, 0x00, 0x34, 0x12}));
  EXPECT_EQ(enc(Output21{false, true, false, false, true, 0}, 4), (Bytes{0x42, 0, 0, 0}));
  EXPECT_EQ(enc(Output21{false, false, false, true, false, 0}, 4), (Bytes{0x20, 0, 0, 0}));
  Output21 o;
  ASSERT_TRUE(decode(Bytes{0x98, 0xFF, 0x10, 0x00}, o)) << "only reserved bits b3, b4, b7 set";
  EXPECT_EQ(o, (Output21{false, false, false, false, false, 16}));
  ASSERT_TRUE(decode(Bytes{0x67, 0x00, 0x34, 0x12}, o));
  EXPECT_EQ(o, all);
}

TEST(AcdriveAssemblies, Input70_Table3_7_2) {
  // Faulted b0, Running1 b2; Speed Actual 6316 = 789.5 rpm at scale 3 (§6.1).
  EXPECT_EQ(enc(Input70{true, true, 6316}, 4), (Bytes{0x05, 0x00, 0xAC, 0x18}));
  EXPECT_EQ(enc(Input70{false, false, 0}, 4), (Bytes{0, 0, 0, 0}))
      << "§2: the sender sets reserved input bits to 0";
}

TEST(AcdriveAssemblies, Input71_Table3_7_2) {
  Input71 i;
  i.at_reference = true;   // b7
  i.ref_from_net = true;   // b6
  i.ctrl_from_net = true;  // b5
  i.ready = true;          // b4
  i.running1 = true;       // b2
  i.state = DriveState::Enabled;
  i.speed_actual = -8;
  EXPECT_EQ(enc(i, 4), (Bytes{0xF4, 0x04, 0xF8, 0xFF}));
  Input71 j;
  j.faulted = true;   // b0
  j.warning = true;   // b1
  j.running2 = true;  // b3
  j.state = DriveState::Faulted;
  EXPECT_EQ(enc(j, 4), (Bytes{0x0B, 0x07, 0, 0}));
  Input71 d;
  ASSERT_TRUE(decode(Bytes{0xF4, 0x04, 0xF8, 0xFF}, d));
  EXPECT_EQ(d, i);
}

TEST(AcdriveAssemblies, DriveStateCodes_Section5_Table6_3) {
  EXPECT_EQ(static_cast<int>(DriveState::Startup), 1);
  EXPECT_EQ(static_cast<int>(DriveState::NotReady), 2);
  EXPECT_EQ(static_cast<int>(DriveState::Ready), 3);
  EXPECT_EQ(static_cast<int>(DriveState::Enabled), 4);
  EXPECT_EQ(static_cast<int>(DriveState::Stopping), 5);
  EXPECT_EQ(static_cast<int>(DriveState::FaultStop), 6);
  EXPECT_EQ(static_cast<int>(DriveState::Faulted), 7);
  EXPECT_STREQ(to_string(DriveState::FaultStop), "Fault_Stop");
}

TEST(AcdriveAssemblies, ExtendedOutputBitsAtTheirRelayAddresses_Table6_2) {
  // Relay I000xx = 0x20 + 8*byte + bit: the bit number in the 32-bit field
  // is xx - 0x20.
  struct Case {
    bool ExtOutputBits::*bit;
    unsigned relay;
  };
  const std::array<Case, 32> cases = {{
      {&ExtOutputBits::start, 0x20},
      {&ExtOutputBits::jog, 0x21},
      {&ExtOutputBits::rev, 0x22},
      {&ExtOutputBits::excitation, 0x23},
      {&ExtOutputBits::dc_brake, 0x24},
      {&ExtOutputBits::fault_reset2, 0x25},
      {&ExtOutputBits::preset1, 0x26},
      {&ExtOutputBits::preset2, 0x27},
      {&ExtOutputBits::preset3, 0x28},
      {&ExtOutputBits::acc_dec_sel1, 0x29},
      {&ExtOutputBits::acc_dec_sel2, 0x2A},
      {&ExtOutputBits::mrh_up, 0x2B},
      {&ExtOutputBits::mrh_down, 0x2C},
      {&ExtOutputBits::spd_hold, 0x2D},
      {&ExtOutputBits::s_arc_off, 0x2E},
      {&ExtOutputBits::max_spd_reduce, 0x2F},
      {&ExtOutputBits::droop_off, 0x30},
      {&ExtOutputBits::atr_mode, 0x31},
      {&ExtOutputBits::rev_gnd, 0x32},
      {&ExtOutputBits::ex_fail1, 0x33},
      {&ExtOutputBits::ex_fail2, 0x34},
      {&ExtOutputBits::ex_fail3, 0x35},
      {&ExtOutputBits::ex_fail4, 0x36},
      {&ExtOutputBits::ex_fail1_no86a, 0x37},
      {&ExtOutputBits::ex_fail2_no86a, 0x38},
      {&ExtOutputBits::ex_fail3_no86a, 0x39},
      {&ExtOutputBits::ex_fail4_no86a, 0x3A},
      {&ExtOutputBits::trace_trg, 0x3B},
      {&ExtOutputBits::second_motor, 0x3C},
      {&ExtOutputBits::emg_stop, 0x3D},
      {&ExtOutputBits::pgm_next, 0x3E},
      {&ExtOutputBits::spd_ref_term, 0x3F},
  }};
  for (const Case& c : cases) {
    ExtOutput o;
    o.instance = 100;
    o.bits.*c.bit = true;
    Bytes want(8, 0);
    const unsigned n = c.relay - 0x20;
    want[n / 8] = static_cast<std::uint8_t>(1U << (n % 8));
    EXPECT_EQ(enc(o, 8), want) << "relay I000" << std::hex << c.relay;
    ExtOutput d;
    d.instance = 100;
    ASSERT_TRUE(decode(want, d));
    EXPECT_TRUE(d.bits.*c.bit);
    EXPECT_EQ(d.bits.pack(), 1U << n);
  }
}

TEST(AcdriveAssemblies, ExtendedOutputWords_Table6_2) {
  ExtOutput o;
  o.instance = 108;      // 12 words
  o.speed_ref2 = 20000;  // top speed, 0x4E20
  o.torque_ref = 5000;   // 100 %, 0x1388
  o.day = 31;
  o.month = 12;
  o.minute = 59;
  o.hour = 23;
  o.plc_registers = {0x0101, 0x0202, 0x0303, 0x0404, 0x0505, 0x0606};
  const Bytes b = enc(o, 24);
  EXPECT_EQ(b, (Bytes{0, 0, 0, 0, 0x20, 0x4E, 0x88, 0x13, 31, 12, 59, 23,
                      1, 1, 2, 2, 3,    3,    4,    4,    5,  5,  6,  6}));
  // Instance 100: 4 words; date, time and PLC words are not sent.
  o.instance = 100;
  EXPECT_EQ(enc(o, 8), (Bytes{0, 0, 0, 0, 0x20, 0x4E, 0x88, 0x13}));
  // 101 carries the date (word 5), 102 the time (word 6).
  o.instance = 101;
  EXPECT_EQ(enc(o, 10), (Bytes{0, 0, 0, 0, 0x20, 0x4E, 0x88, 0x13, 31, 12}));
  Bytes wrong(10, 0);
  o.instance = 100;
  EXPECT_FALSE(encode(o, wrong)) << "instance 100 is 8 bytes";
  ExtOutput d;
  d.instance = 108;
  ASSERT_TRUE(decode(b, d));
  o.instance = 108;
  EXPECT_EQ(d, o);
}

TEST(AcdriveAssemblies, ExtendedInputStatusAndFaultField_Table6_3) {
  ExtInput i;
  i.instance = 120;
  i.status.gate_active = true;           // byte 0 b7
  i.status.run_or_jog_input = true;      // byte 0 b0
  i.status.ext_db_or_comm_error = true;  // byte 1 b2
  i.status.ext_signal4 = true;           // byte 1 b7
  i.faults = fault_bit(1) | fault_bit(18) | fault_bit(32);
  i.detect.setting_reached = true;      // byte 6 b7
  i.detect.cooling_fan_failure = true;  // byte 7 b7
  i.detect.torque_detect = true;        // byte 7 b0
  i.speed_actual2 = 20000;
  i.arc_out = -20000;
  EXPECT_EQ(enc(i, 12),
            (Bytes{0x81, 0x84, 0x01, 0x00, 0x02, 0x80, 0x80, 0x81, 0x20, 0x4E, 0xE0, 0xB1}));
  // Fault field by table cell: code 1 overcurrent = byte 2 b0; code 9 start
  // stall = byte 3 b0; code 18 comm timeout = byte 4 b1; code 29 external
  // fault 1 = byte 5 b4; code 32 external fault 4 = byte 5 b7.
  const std::array<std::pair<unsigned, std::pair<unsigned, unsigned>>, 6> cells = {
      {{1, {2, 0}}, {6, {2, 5}}, {9, {3, 0}}, {18, {4, 1}}, {29, {5, 4}}, {32, {5, 7}}}};
  for (auto [code, cell] : cells) {
    ExtInput f;
    f.instance = 120;
    f.faults = fault_bit(code);
    const Bytes b = enc(f, 12);
    EXPECT_EQ(b[cell.first], 1U << cell.second) << "code " << code;
  }
}

TEST(AcdriveAssemblies, ExtendedInputReservedBitsAreZero_Section2) {
  ExtInput i;
  i.instance = 132;
  // Every named bit on: byte 1 b3 and byte 6 b0 have no name and stay 0.
  i.status = ExtStatusBits{true, true, true, true, true, true, true, true,
                           true, true, true, true, true, true, true};
  i.detect = ExtDetectBits{true, true, true, true, true, true, true, true,
                           true, true, true, true, true, true, true};
  const Bytes b = enc(i, 36);
  EXPECT_EQ(b[0], 0xFF);
  EXPECT_EQ(b[1], 0xF7);
  EXPECT_EQ(b[6], 0xFE);
  EXPECT_EQ(b[7], 0xFF);
}

TEST(AcdriveAssemblies, ExtendedInputMonitorWordsByInstance_Table6_3) {
  ExtInput i;
  i.speed_actual2 = 1;
  i.arc_out = 2;
  i.motor_current = 3;
  i.torque_command = 4;
  i.dc_voltage = 5;
  i.output_voltage = 6;
  i.output_frequency = 7;
  i.ol_precounter = 8;
  i.motor_temperature = 9;
  i.motor_flux = 10;
  i.plc_registers = {11, 12, 13, 14};
  i.instance = 132;
  const Bytes b = enc(i, 36);
  // Word k (1-based) at bytes 2k-2..2k-1: words 5..18 carry 1..14.
  for (unsigned w = 5; w <= 18; ++w) {
    EXPECT_EQ(b[2 * w - 2], w - 4) << "word " << w;
    EXPECT_EQ(b[2 * w - 1], 0);
  }
  i.instance = 127;  // 13 words: motor flux (word 14) first appears in 128
  const Bytes c = enc(i, 26);
  EXPECT_EQ(c[24], 9) << "motor temperature, word 13";
  ExtInput d;
  ASSERT_TRUE(decode(c, d));
  EXPECT_EQ(d.instance, 127);
  EXPECT_EQ(d.motor_flux, 0);
  EXPECT_EQ(d.motor_temperature, 9);
  ASSERT_TRUE(decode(b, d));
  EXPECT_EQ(d.plc_registers[3], 14);
  EXPECT_FALSE(decode(Bytes(13, 0), d)) << "no instance is 13 bytes";
}

TEST(AcdriveAssemblies, Instance140ProtectCodeAndMonitors_Table6_3_Table6_5) {
  Input140 i;
  i.status.inverter_running = true;  // byte 0 b1
  i.status.dc_braking = true;        // byte 1 b1
  i.status.ext_signal1 = true;       // not in 140: dropped
  i.protect_code = 18;
  i.monitor = {0x1234, 0x5678, 0x9ABC};
  // byte 1: PEC 18 in b7..b2 = 0x48, plus DC braking b1.
  EXPECT_EQ(enc(i, 8), (Bytes{0x02, 0x4A, 0x34, 0x12, 0x78, 0x56, 0xBC, 0x9A}));
  Bytes lit(8, 0);
  ASSERT_TRUE(encode(i, lit, MonitorByteOrder::ManualLiteral));
  EXPECT_EQ(lit, (Bytes{0x02, 0x4A, 0x34, 0x12, 0x56, 0x78, 0x9A, 0xBC}))
      << "§13.4 item 6: monitors 2 and 3 printed high byte first";
  Input140 d;
  ASSERT_TRUE(decode(lit, d, MonitorByteOrder::ManualLiteral));
  EXPECT_EQ(d.protect_code, 18);
  EXPECT_EQ(d.monitor[1], 0x5678);
  EXPECT_TRUE(d.status.dc_braking);
  EXPECT_FALSE(d.status.ext_signal1);
  Input140 e;
  e.protect_code = 32;
  EXPECT_EQ(enc(e, 8)[1], 0x80);
}

TEST(AcdriveAssemblies, J12MonitorCombinations_Table6_5_1) {
  using M = std::array<std::uint8_t, 3>;
  EXPECT_EQ(monitor_selection(0), (M{1, 2, 3}));
  EXPECT_EQ(monitor_selection(3), (M{1, 2, 6})) << "default";
  EXPECT_EQ(monitor_selection(30), (M{1, 7, 8}));
  EXPECT_EQ(monitor_selection(35), (M{1, 9, 10}));
  EXPECT_EQ(monitor_selection(36), (M{2, 3, 4}));
  EXPECT_EQ(monitor_selection(60), (M{2, 7, 10}));
  EXPECT_EQ(monitor_selection(63), (M{2, 9, 10}));
  EXPECT_EQ(monitor_selection(64), (M{3, 4, 5}));
  EXPECT_EQ(monitor_selection(90), (M{4, 6, 7}));
  EXPECT_EQ(monitor_selection(100), (M{5, 6, 7}));
  EXPECT_EQ(monitor_selection(110), (M{6, 7, 8}));
  EXPECT_EQ(monitor_selection(116), (M{7, 8, 9}));
  EXPECT_EQ(monitor_selection(119), (M{8, 9, 10}));
  EXPECT_EQ(monitor_selection(120), (M{0, 0, 0}));
}

TEST(AcdriveAssemblies, SpeedScaleWorkedExamples_Section6_1_Section6_2) {
  EXPECT_DOUBLE_EQ(bus_to_rpm(4567, 3), 570.875);
  EXPECT_EQ(rpm_to_bus(789.5, 3), std::int16_t{6316});
  EXPECT_EQ(rpm_to_bus(0.125, 3), std::int16_t{1}) << "1 LSB = 0.125 r/min at the default scale";
  // V/f: 30 Hz, A-06 = 4 poles, scale 3 -> 7200 (the manual's example, x 60).
  EXPECT_EQ(rpm_to_bus(hz_to_rpm(30, 4), 3), std::int16_t{7200});
  EXPECT_DOUBLE_EQ(rpm_to_hz(bus_to_rpm(7200, 3), 4), 30);
  // §13.3: +-4095.875 r/min at scale 3; a smaller scale reaches further.
  EXPECT_EQ(rpm_to_bus(4095.875, 3), std::int16_t{32767});
  EXPECT_FALSE(rpm_to_bus(4096, 3).has_value());
  EXPECT_EQ(rpm_to_bus(8191.75, 2), std::int16_t{32767});
  EXPECT_EQ(rpm_to_bus(-4096, 3), std::int16_t{-32768});
  EXPECT_FALSE(rpm_to_bus(std::numeric_limits<double>::infinity(), 3).has_value());
  EXPECT_DOUBLE_EQ(bus_to_rpm(100, -2), 400) << "negative scale: 1 LSB = 4 r/min";
}

TEST(AcdriveAssemblies, ProtectCodes_Table6_4) {
  EXPECT_STREQ(protect_code_text(0), "No fault / protection");
  EXPECT_STREQ(protect_code_text(1), "Overcurrent protection");
  EXPECT_STREQ(protect_code_text(3), "");
  EXPECT_STREQ(protect_code_text(18), "Communication timeout error");
  EXPECT_STREQ(protect_code_text(25), "CPU abnormal processing");
  EXPECT_STREQ(protect_code_text(32), "External fault 4");
  EXPECT_STREQ(protect_code_text(33), "");
  EXPECT_FALSE(is_defined_protect_code(4));
  EXPECT_TRUE(is_defined_protect_code(5));
  // §7.8: the lowest code wins.
  EXPECT_EQ(lowest_protect_code(fault_bit(20) | fault_bit(7)), 7);
  EXPECT_EQ(lowest_protect_code(0), 0);
  EXPECT_EQ(lowest_protect_code(0x80000000U), 32);
}

}  // namespace plc::acdrive

// The simulated PR5510 driven through raw window bytes, checked against the
// tables of shared/specs/sartorius-pr1721.md (section named per test).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "plc/fb/weighing/window_codec.hpp"
#include "plc/io/device_model.hpp"
#include "pr5510/display_rounding.hpp"
#include "pr5510/filling_process.hpp"
#include "pr5510_harness.hpp"

namespace wg = plc::weighing;
using wtest::Harness;
using wtest::quiet_config;
using namespace std::chrono_literals;

namespace {

wg::StatusBits st(Harness& h) { return wg::decode_status(h.r()); }

// Select `code` in W[4], wait two device cycles, return R[0..3] as DINT.
std::int32_t read_code(Harness& h, std::uint8_t code, wg::Bus bus) {
  h.w()[wg::w::kReadValueSelect] = code;
  h.run(40ms);
  EXPECT_EQ(code, h.r()[wg::r::kReadValueSelected]) << "echo of code " << int(code);
  return wg::decode_dint(h.r(), bus);
}

// Full write handshake (§3.6) by hand; returns Cmd_Error at acknowledge.
bool write_code(Harness& h, std::uint8_t code, std::int32_t v, wg::Bus bus) {
  EXPECT_FALSE(st(h).WriteActive);
  wg::encode_dint(h.w(), v, bus);
  h.w()[wg::w::kWriteValueSelect] = code;
  for (int i = 0; i < 400 && !st(h).WriteActive; ++i) h.run(1ms);
  EXPECT_TRUE(st(h).WriteActive) << "no Write_Active for code " << int(code);
  const bool err = st(h).CmdError;
  h.w()[wg::w::kWriteValueSelect] = 0;
  h.run(40ms);
  EXPECT_FALSE(st(h).WriteActive);
  return err;
}

// A W[7] command as a 60 ms edge (§3.3: hold >= 40 ms).
void pulse(Harness& h, wg::CommandBit b) {
  h.w()[wg::w::kCommands] = static_cast<std::uint8_t>(1U << static_cast<unsigned>(b));
  h.run(60ms);
  h.w()[wg::w::kCommands] = 0;
  h.run(60ms);
}

class BothBuses : public ::testing::TestWithParam<wg::Bus> {};

}  // namespace

// §0: the windows are processed every 20 ms; R is frozen in between.
TEST(Pr5510Model, Spec0_WindowsUpdateEvery20ms) {
  auto c = quiet_config();
  c.filling.initial_load = 1.0;
  Harness h(c);
  h.w()[wg::w::kReadValueSelect] = 0x08;
  h.run(19ms);
  EXPECT_EQ(0, h.r()[wg::r::kReadValueSelected]);
  h.run(1ms);
  EXPECT_EQ(0x08, h.r()[wg::r::kReadValueSelected]);
  h.run(5ms);
  h.w()[wg::w::kReadValueSelect] = 0x0E;
  h.run(14ms);  // t = 39 ms
  EXPECT_EQ(0x08, h.r()[wg::r::kReadValueSelected]);
  h.run(1ms);
  EXPECT_EQ(0x0E, h.r()[wg::r::kReadValueSelected]);
  EXPECT_EQ(2u, h.model.cycles());
}

// §0 with the process moving: while the coarse and fine valves fill the
// hopper (the weight changes every 1 ms tick, noise on), the whole read
// window changes only in the steps that ran a device cycle, and it does
// follow the weight at those. The usual step (no cycle due) hands the
// window over before its ticks (a35fe87), which is exact only while the
// ticks never write it: this test fails if one does.
TEST(Pr5510Model, Spec0_ReadWindowFrozenBetweenCyclesWhileFilling) {
  plc::sim::Pr5510Config c;  // the default noise and flow variation
  c.filling.initial_load = 1.0;
  Harness h(c);
  h.w()[wg::w::kReadValueSelect] = 0x08;  // gross (§5.2)
  h.w()[wg::w::kOutputs] = 0x03;          // outputs 1 and 2: coarse and fine valves
  std::array<std::uint8_t, wg::kWindowSize> before{};
  std::copy_n(h.r().begin(), wg::kWindowSize, before.begin());
  int changes_at_cycles = 0;
  for (int ms = 1; ms <= 2000; ++ms) {
    const auto cycles_before = h.model.cycles();
    h.run(1ms);
    const bool cycled = h.model.cycles() != cycles_before;
    const bool changed = !std::equal(before.begin(), before.end(), h.r().begin());
    if (!cycled) {
      ASSERT_FALSE(changed) << "R changed between device cycles at t = " << ms << " ms";
    }
    if (cycled && changed) ++changes_at_cycles;
    std::copy_n(h.r().begin(), wg::kWindowSize, before.begin());
  }
  EXPECT_EQ(100u, h.model.cycles());  // 2 s of 20 ms cycles
  EXPECT_GT(changes_at_cycles, 50) << "the gross weight did not follow the filling";
}

// §5.2 read codes and §5.3 packed codes 4/5, in both byte orders (§3).
TEST_P(BothBuses, Spec52_53_EveryReadCode) {
  const wg::Bus bus = GetParam();
  auto c = quiet_config(bus);
  c.filling.initial_load = 12.34;
  c.division = 1;
  Harness h(c);
  h.run(500ms);
  EXPECT_EQ(1234, read_code(h, 0x08, bus));    // gross, digits (2 decimals)
  EXPECT_EQ(1234, read_code(h, 0x09, bus));    // net = gross without tare
  EXPECT_EQ(0, read_code(h, 0x0A, bus));       // tare
  EXPECT_EQ(123400, read_code(h, 0x0C, bus));  // gross x 100 ([INFERRED])
  EXPECT_EQ(5000, read_code(h, 0x0E, bus));    // FSD 50.00 kg
  const auto f = wg::unpack_format(static_cast<std::uint32_t>(read_code(h, 0x04, bus)));
  EXPECT_EQ((wg::FormatInfo{2, 0x03, 1, 0}), f);  // 2 decimals, kg, d = 1, no error
  const auto m = wg::unpack_model(static_cast<std::uint32_t>(read_code(h, 0x05, bus)));
  EXPECT_EQ((wg::ModelInfo{0x5510, 0x0312}), m);
  // Raw byte positions: Profibus MSB first, DeviceNet LSB first.
  h.w()[wg::w::kReadValueSelect] = 0x08;
  h.run(40ms);
  if (bus == wg::Bus::Profibus) {
    EXPECT_EQ(0x04, h.r()[2]);
    EXPECT_EQ(0xD2, h.r()[3]);  // 1234 = 0x04D2
  } else {
    EXPECT_EQ(0xD2, h.r()[0]);
    EXPECT_EQ(0x04, h.r()[1]);
  }
  // After a tare: tare = gross, net = 0 (§5.5 Set tare).
  pulse(h, wg::CommandBit::SetTare);
  EXPECT_TRUE(st(h).TareActive);
  EXPECT_EQ(1234, read_code(h, 0x0A, bus));
  EXPECT_EQ(0, read_code(h, 0x09, bus));
  h.model.process().add_load(1.0);
  h.run(500ms);
  EXPECT_EQ(100, read_code(h, 0x09, bus));
  EXPECT_EQ(1334, read_code(h, 0x08, bus));
}

// §5.3 [AMBIG] 9: the CC-Link word order is selectable in the model too.
TEST(Pr5510Model, Spec53_PackedOrderCcLink) {
  auto c = quiet_config();
  c.packed_order = wg::PackedOrder::CcLink;
  Harness h(c);
  const auto v = static_cast<std::uint32_t>(read_code(h, 0x05, wg::Bus::Profibus));
  EXPECT_EQ(0x03125510u, v);
}

// §7.1 [INFERRED]: unknown codes echo with 0; strict mode does not echo.
TEST(Pr5510Model, Spec71_ReservedReadCodes) {
  Harness h(quiet_config());
  EXPECT_EQ(0, read_code(h, 0x06, wg::Bus::Profibus));
  auto c = quiet_config();
  c.strict_codes = true;
  Harness s(c);
  s.w()[wg::w::kReadValueSelect] = 0x06;
  s.run(100ms);
  EXPECT_EQ(0, s.r()[wg::r::kReadValueSelected]);
}

// §3.4 R[6].1 and R[5].6: set at power-on; reading FSD (0x0E) clears
// Cal_Changed; Res Power (W[7].5 or code 0x75) clears Power_Fail.
TEST(Pr5510Model, Spec34_PowerFailAndCalChanged) {
  Harness h(quiet_config());
  h.run(40ms);
  EXPECT_TRUE(st(h).PowerFail);
  EXPECT_TRUE(st(h).CalChanged);
  read_code(h, 0x08, wg::Bus::Profibus);
  EXPECT_TRUE(st(h).CalChanged);
  read_code(h, 0x0E, wg::Bus::Profibus);
  EXPECT_FALSE(st(h).CalChanged);
  pulse(h, wg::CommandBit::ResPower);
  EXPECT_FALSE(st(h).PowerFail);
  // (With W[4] left at 0x0E the restarted device would serve FSD at once
  // and clear Cal_Changed again in its first cycle.)
  h.w()[wg::w::kReadValueSelect] = 0x08;
  h.model.power_cycle();
  h.run(40ms);
  EXPECT_TRUE(st(h).PowerFail);
  EXPECT_TRUE(st(h).CalChanged);
  EXPECT_FALSE(write_code(h, 0x75, 0, wg::Bus::Profibus));
  EXPECT_FALSE(st(h).PowerFail);
}

// §3.6 write procedure and §4.1 example (0x84, 4660): ack by Write_Active,
// no re-trigger while W[5] stays, reset when W[5] = 0. Both buses.
TEST_P(BothBuses, Spec36_WriteHandshakeApplicationCode) {
  const wg::Bus bus = GetParam();
  Harness h(quiet_config(bus));
  h.run(40ms);
  wg::encode_dint(h.w(), 4660, bus);
  h.w()[wg::w::kWriteValueSelect] = 0x84;
  h.run(20ms);
  EXPECT_TRUE(st(h).WriteActive);
  EXPECT_FALSE(st(h).CmdError);
  const auto accepted = h.model.commands_accepted();
  h.run(200ms);  // W[5] unchanged: no second execution
  EXPECT_EQ(accepted, h.model.commands_accepted());
  EXPECT_TRUE(st(h).WriteActive);
  h.w()[wg::w::kWriteValueSelect] = 0;
  h.run(20ms);
  EXPECT_FALSE(st(h).WriteActive);
  EXPECT_EQ(4660, read_code(h, 0x84, bus));  // application register bank
  EXPECT_FALSE(write_code(h, 0x84, -7, bus));
  EXPECT_EQ(-7, read_code(h, 0x84, bus));
}

// §5.4 every firmware write code 0x70..0x75, Limit1 On (0x18), and an
// undefined code (acknowledged with Cmd_Error, [INFERRED]).
TEST_P(BothBuses, Spec54_EveryWriteCode) {
  const wg::Bus bus = GetParam();
  auto c = quiet_config(bus);
  c.filling.initial_load = 0.4;  // inside the zero-set range (1 kg)
  Harness h(c);
  h.run(500ms);
  EXPECT_EQ(40, read_code(h, 0x08, bus));
  EXPECT_FALSE(write_code(h, 0x70, 0, bus));  // set zero
  EXPECT_EQ(0, read_code(h, 0x08, bus));
  h.model.process().add_load(2.0);
  h.run(500ms);
  EXPECT_FALSE(write_code(h, 0x71, 0, bus));  // set tare
  EXPECT_TRUE(st(h).TareActive);
  EXPECT_EQ(200, read_code(h, 0x0A, bus));
  EXPECT_FALSE(write_code(h, 0x72, 0, bus));  // reset tare
  EXPECT_FALSE(st(h).TareActive);
  EXPECT_EQ(0, read_code(h, 0x0A, bus));
  EXPECT_FALSE(write_code(h, 0x73, 0, bus));  // start analog test
  EXPECT_TRUE(st(h).TestActive);
  EXPECT_EQ(500, read_code(h, 0x08, bus));    // test value 5.00 kg
  EXPECT_FALSE(write_code(h, 0x74, 0, bus));  // end analog test
  EXPECT_FALSE(st(h).TestActive);
  EXPECT_EQ(200, read_code(h, 0x08, bus));
  EXPECT_TRUE(st(h).PowerFail);
  EXPECT_FALSE(write_code(h, 0x75, 0, bus));  // reset power-fail
  EXPECT_FALSE(st(h).PowerFail);
  EXPECT_FALSE(write_code(h, 0x18, 150, bus));  // Limit1 On at 1.50 kg
  EXPECT_TRUE(st(h).Limit1);                    // net 2.00 >= 1.50
  EXPECT_FALSE(write_code(h, 0x18, 250, bus));
  EXPECT_FALSE(st(h).Limit1);
  EXPECT_TRUE(write_code(h, 0x40, 1, bus));   // 0x40: not in the §5.4 table
  EXPECT_FALSE(write_code(h, 0x19, 0, bus));  // the next accepted one clears Cmd_Error
  EXPECT_FALSE(st(h).CmdError);
}

// §3.3 W[7] bits 0..5 act on the rising edge; a held bit does not repeat.
TEST_P(BothBuses, Spec33_EveryCommandBitOnRisingEdge) {
  auto c = quiet_config(GetParam());
  c.filling.initial_load = 0.3;
  Harness h(c);
  h.run(500ms);
  pulse(h, wg::CommandBit::SetZero);
  EXPECT_EQ(0, h.model.gross_digits());
  h.model.process().add_load(1.5);
  h.run(500ms);
  pulse(h, wg::CommandBit::SetTare);
  EXPECT_TRUE(st(h).TareActive);
  EXPECT_EQ(150, h.model.tare_digits());
  pulse(h, wg::CommandBit::ResTare);
  EXPECT_FALSE(st(h).TareActive);
  pulse(h, wg::CommandBit::SetTest);
  EXPECT_TRUE(st(h).TestActive);
  pulse(h, wg::CommandBit::ResTest);
  EXPECT_FALSE(st(h).TestActive);
  pulse(h, wg::CommandBit::ResPower);
  EXPECT_FALSE(st(h).PowerFail);
  // Held high: one execution only.
  const auto n = h.model.commands_accepted();
  h.w()[wg::w::kCommands] = 1U << static_cast<unsigned>(wg::CommandBit::SetTare);
  h.run(500ms);
  EXPECT_EQ(n + 1, h.model.commands_accepted());
}

// §3.3 W[6] outputs 1-3 (level) reflected in R[5] bits 3-5; §3.4 Inp 1-3.
TEST(Pr5510Model, Spec33_34_DigitalOutputsAndInputs) {
  Harness h(quiet_config());
  h.w()[wg::w::kOutputs] = 0x05;
  h.run(20ms);
  EXPECT_TRUE(st(h).Out1);
  EXPECT_FALSE(st(h).Out2);
  EXPECT_TRUE(st(h).Out3);
  EXPECT_EQ(0x28, h.r()[wg::r::kStatus] & 0x38);
  h.model.set_input(2, true);
  h.run(20ms);
  EXPECT_TRUE(st(h).Inp2);
  EXPECT_EQ(0x10, h.r()[wg::r::kCommand] & 0x38);
}

// Issue 21 follow-up, point 8 [INFERRED, pr5510_model.hpp]: a lost I/O
// connection turns outputs 1-3 off at once (W[6], §3.3; R[5].3-5, §3.4).
// A host that calls step() delivers the outputs every cycle - the sim
// plugin, the PROFINET device once its AR is up again (PnDevice calls
// step(), not step_io()) - so its next step is a new message and the
// outputs follow W[6] again. Before, only step_io(new_message) ended the
// loss: behind a PROFINET device the valves stayed closed for good after an
// AR loss.
TEST(Pr5510Model, Spec33_34_OutputsOffAfterAConnectionLossUntilTheNextMessage) {
  Harness h(quiet_config());
  h.w()[wg::w::kOutputs] = 0x05;
  h.run(20ms);
  ASSERT_TRUE(st(h).Out1);
  h.model.io_connection_lost();
  EXPECT_TRUE(h.model.master_lost());
  EXPECT_FALSE(h.model.status().Out1 || h.model.status().Out3);
  h.run(40ms);  // the host steps the model again with its outputs
  EXPECT_FALSE(h.model.master_lost());
  EXPECT_TRUE(st(h).Out1);
  EXPECT_TRUE(st(h).Out3);
}

// §3.4 R[7] weighing status: center zero, below zero, inside ZSR, above
// FSD, over-load, dimmed, A/D error; error 35 as last error (§5.3).
TEST(Pr5510Model, Spec34_WeighingStatusRanges) {
  Harness h(quiet_config());
  h.run(500ms);
  EXPECT_TRUE(st(h).CenterZero);
  EXPECT_TRUE(st(h).InsideZsr);
  EXPECT_FALSE(st(h).BelowZero);
  EXPECT_TRUE(st(h).StandStill);
  h.model.process().add_load(-0.05);  // below zero (e.g. a lifted hopper)
  h.run(500ms);
  EXPECT_TRUE(st(h).BelowZero);
  EXPECT_TRUE(st(h).Dimmed);
  EXPECT_FALSE(st(h).CenterZero);
  h.model.process().add_load(50.05);  // exactly FSD
  h.run(500ms);
  EXPECT_TRUE(st(h).AboveFsd);
  EXPECT_TRUE(st(h).Dimmed);
  EXPECT_FALSE(st(h).Overload);
  EXPECT_FALSE(st(h).InsideZsr);
  EXPECT_EQ(35, h.model.last_error());
  h.model.process().add_load(5.0);  // FSD + overload value
  h.run(500ms);
  EXPECT_TRUE(st(h).Overload);
  h.model.set_adu_error(true);
  h.run(20ms);
  EXPECT_TRUE(st(h).AduError);
}

// §5.3 calibration errors 40, 41, 42 and 46 (front-panel calibration, the
// only way to calibrate: the windows have no calibration command), and
// §3.4 R[5].1 Cal Changed after a calibration.
TEST(Pr5510Model, Spec53_CalibrationErrors40_41_42_46) {
  auto last_error_read = [](Harness& h) {
    return wg::unpack_format(static_cast<std::uint32_t>(read_code(h, 0x04, wg::Bus::Profibus)))
        .last_error;
  };
  auto locked = quiet_config();
  locked.cal_switch_locked = true;
  Harness l(locked);
  l.run(500ms);
  EXPECT_FALSE(l.model.panel_start_calibration());
  EXPECT_EQ(40, last_error_read(l));
  EXPECT_FALSE(l.model.calibrating());

  auto c = quiet_config();
  c.filling.initial_load = 10.0;
  Harness h(c);
  h.run(500ms);
  EXPECT_FALSE(h.model.panel_calibrate_span(10.0));
  EXPECT_EQ(41, last_error_read(h));
  EXPECT_FALSE(h.model.panel_finish_calibration());
  EXPECT_EQ(41, h.model.last_error());
  // A tare waiting for standstill: starting calibration is error 46.
  h.w()[wg::w::kOutputs] = 0x01;  // coarse valve: no standstill
  h.run(300ms);
  h.w()[wg::w::kCommands] = 1U << 1;
  h.run(60ms);
  h.w()[wg::w::kCommands] = 0;
  ASSERT_TRUE(st(h).CmdBusy);
  EXPECT_FALSE(h.model.panel_start_calibration());
  EXPECT_EQ(46, last_error_read(h));
  h.w()[wg::w::kOutputs] = 0;
  h.run(4000ms);  // the tare ends (error 31 or done)
  ASSERT_FALSE(st(h).CmdBusy);
  // Read the full-scale code once to clear Cal Changed (set at power-on).
  read_code(h, 0x0E, wg::Bus::Profibus);
  h.run(60ms);
  ASSERT_FALSE(st(h).CalChanged);
  // In calibration mode a window tare or zero is refused with 42.
  ASSERT_TRUE(h.model.panel_start_calibration());
  pulse(h, wg::CommandBit::SetTare);
  EXPECT_TRUE(st(h).CmdError);
  EXPECT_EQ(42, last_error_read(h));
  pulse(h, wg::CommandBit::SetZero);
  EXPECT_EQ(42, h.model.last_error());
  // A span calibration declares the load on the scale to be 12.5 kg: it
  // then reads 1250 digits of 0.01 kg, and every change is stretched by the
  // same factor.
  const double before = h.model.gross_digits();
  ASSERT_GT(before, 1000.0);
  ASSERT_TRUE(h.model.panel_calibrate_span(12.5));
  ASSERT_TRUE(h.model.panel_finish_calibration());
  h.run(500ms);
  EXPECT_TRUE(st(h).CalChanged);
  EXPECT_NEAR(h.model.gross_digits(), 1250, 2);
  h.model.process().add_load(2.0);
  h.run(1000ms);
  EXPECT_NEAR(h.model.gross_digits() - 1250, 200.0 * 1250.0 / before, 3.0);
  // Out of calibration mode the tare works again.
  pulse(h, wg::CommandBit::SetTare);
  h.run(500ms);
  EXPECT_TRUE(st(h).TareActive);
  EXPECT_FALSE(st(h).CmdError);
}

// §3.4 R[7].6 Stand-Still: set when stable, lost while material lands.
TEST(Pr5510Model, Spec34_StandStillWhileFilling) {
  Harness h(quiet_config());
  h.run(500ms);
  EXPECT_TRUE(st(h).StandStill);
  h.w()[wg::w::kOutputs] = 0x01;  // coarse valve
  h.run(600ms);
  EXPECT_FALSE(st(h).StandStill);
  h.w()[wg::w::kOutputs] = 0x00;
  h.run(1000ms);
  EXPECT_TRUE(st(h).StandStill);
}

// §5.3 errors 47 (zero outside the range), 31 (no standstill), 33 (W&M).
TEST(Pr5510Model, Spec53_CommandErrors47_31_33) {
  auto c = quiet_config();
  c.filling.initial_load = 3.0;  // zero-set range is 1 kg
  Harness h(c);
  h.run(500ms);
  pulse(h, wg::CommandBit::SetZero);
  EXPECT_TRUE(st(h).CmdError);
  EXPECT_EQ(47, h.model.last_error());
  EXPECT_EQ(47, wg::unpack_format(static_cast<std::uint32_t>(read_code(h, 0x04, wg::Bus::Profibus)))
                    .last_error);
  // Tare while the coarse valve runs: Cmd_Busy, then error 31 after 3 s.
  h.w()[wg::w::kOutputs] = 0x01;
  h.run(300ms);
  h.w()[wg::w::kCommands] = 1U << 1;
  h.run(60ms);
  h.w()[wg::w::kCommands] = 0;
  EXPECT_TRUE(st(h).CmdBusy);
  EXPECT_FALSE(st(h).CmdError);  // cleared by the accepted command
  h.run(3000ms);
  EXPECT_FALSE(st(h).CmdBusy);
  EXPECT_TRUE(st(h).CmdError);
  EXPECT_EQ(31, h.model.last_error());
  h.w()[wg::w::kOutputs] = 0;
  // W&M mode: tare of a negative weight is error 33.
  auto wm = quiet_config();
  wm.legal_for_trade = true;
  Harness m(wm);
  m.model.process().add_load(-0.2);
  m.run(500ms);
  EXPECT_TRUE(write_code(m, 0x71, 0, wg::Bus::Profibus));
  EXPECT_EQ(33, m.model.last_error());
}

// Filling process: coarse/fine rates and material in flight after closing.
TEST(Pr5510Model, FillingRatesAndInFlight) {
  Harness h(quiet_config());
  h.w()[wg::w::kOutputs] = 0x02;  // fine valve: 0.5 kg/s
  h.run(2000ms);
  const double in_flight = h.model.process().in_flight();
  EXPECT_NEAR(0.5 * 0.25, in_flight, 0.01);  // rate x fall time
  h.w()[wg::w::kOutputs] = 0x00;
  const double at_close = h.model.process().load();
  h.run(1000ms);
  const double landed_after = h.model.process().load() - at_close;
  EXPECT_GT(landed_after, 0.12);  // the in-flight column and the valve tail
  EXPECT_LT(landed_after, 0.16);
  h.w()[wg::w::kOutputs] = 0x01;  // coarse: 5 kg/s
  const double before = h.model.process().load();
  h.run(1000ms);
  EXPECT_NEAR(5.0 * (1.0 - 0.25 - 0.03), h.model.process().load() - before, 0.15);
  h.w()[wg::w::kOutputs] = 0x04;  // discharge empties the hopper
  h.run(3000ms);
  EXPECT_LT(h.model.process().load(), 0.001);
}

// Determinism: the same seed gives the same weights; another seed does not.
TEST(Pr5510Model, SeededNoiseIsDeterministic) {
  auto trace = [](std::uint64_t seed) {
    auto c = quiet_config();
    c.filling.noise_kg = 0.01;
    c.filling.seed = seed;
    Harness h(c);
    h.w()[wg::w::kReadValueSelect] = 0x0C;
    std::uint64_t sum = 0;
    for (int i = 0; i < 50; ++i) {
      h.run(20ms);
      sum = sum * 31 + static_cast<std::uint32_t>(wg::decode_dint(h.r(), wg::Bus::Profibus));
    }
    return sum;
  };
  EXPECT_EQ(trace(7), trace(7));
  EXPECT_NE(trace(7), trace(8));
}

// Registration and params (cell config `params:`).
TEST(Pr5510Model, RegisteredWithParams) {
  const auto* f = plc::io::DeviceModelRegistry::instance().find("pr5510");
  ASSERT_NE(nullptr, f);
  plc::io::ModelParams p;
  p.set("bus", "devicenet");
  p.set("seed", "42");
  p.set("fine_rate", "0.8");
  auto m = (*f)(p);
  ASSERT_NE(nullptr, m);
  auto& model = static_cast<plc::sim::Pr5510Model&>(*m);
  EXPECT_EQ(wg::Bus::DeviceNet, model.config().bus);
  EXPECT_DOUBLE_EQ(0.8, model.config().filling.fine_rate);
  EXPECT_EQ(8u, m->input_size());
  plc::io::ModelParams bad;
  bad.set("bus", "canopen");
  EXPECT_THROW((*f)(bad), plc::io::ParamError);
  plc::io::ModelParams typo;
  typo.set("coarse_rat", "1");
  EXPECT_THROW((*f)(typo), plc::io::ParamError);
}

// "Scale-interface = disable": no data communication (§7.1 [INFERRED]).
TEST(Pr5510Model, Spec71_ScaleInterfaceDisabled) {
  auto c = quiet_config();
  c.scale_interface = false;
  Harness h(c);
  h.w()[wg::w::kReadValueSelect] = 0x08;
  h.run(100ms);
  for (auto b : h.r()) EXPECT_EQ(0, b);
}

// A weight beyond what the display can show (here the analog test value,
// as likely a steep span calibration) saturates at the display limit: Above
// FSD and Over-load (§3.4 R[7]) and a positive gross, never a wrapped DINT
// (found by tests/fuzz/fuzz_weighing_windows: signed overflow in the
// standstill check).
TEST(Pr5510Model, Spec34_WeightBeyondTheDisplaySaturates) {
  auto c = quiet_config();
  c.test_value = 3e7;  // kg: 3e9 digits at 0.01 kg, more than a DINT holds
  Harness h(c);
  h.run(100ms);
  pulse(h, wg::CommandBit::SetTest);
  ASSERT_TRUE(st(h).TestActive);
  h.run(100ms);
  EXPECT_GT(h.model.gross_digits(), 0) << "the display saturates, it does not wrap";
  EXPECT_TRUE(st(h).AboveFsd);
  EXPECT_TRUE(st(h).Overload);
  c.test_value = -3e7;
  Harness low(c);
  low.run(100ms);
  pulse(low, wg::CommandBit::SetTest);
  low.run(100ms);
  EXPECT_LT(low.model.gross_digits(), 0);
  EXPECT_TRUE(st(low).BelowZero);
  EXPECT_FALSE(st(low).AboveFsd);
}

INSTANTIATE_TEST_SUITE_P(Pr5510Model, BothBuses,
                         ::testing::Values(wg::Bus::Profibus, wg::Bus::DeviceNet));

// The display rounding of the model (weight to the display step, 1/100
// digit, spec §3.4 gross and 0x0C read codes) inline: bit for bit
// std::round and std::llround for every double class, halves and the
// neighbours of halves at every magnitude, +-0, 2^52 and around it, the
// infinities and NaN (fails with round-half-even, truncation, or the sign
// of a zero result lost).
TEST(PR5510Rounding, InlineRoundingIsStdRoundAndLlround) {
  namespace r = plc::sim::pr5510_rounding;
  std::vector<double> v = {0.0,
                           -0.0,
                           0.5,
                           -0.5,
                           1.5,
                           -1.5,
                           2.5,
                           -2.5,
                           0.49999999999999994,
                           -0.49999999999999994,
                           4503599627370495.5,
                           -4503599627370495.5,
                           4503599627370496.0,
                           -4503599627370496.0,
                           4503599627370497.0,
                           9007199254740993.0,
                           1e300,
                           -1e300,
                           std::numeric_limits<double>::denorm_min(),
                           -std::numeric_limits<double>::denorm_min(),
                           std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()};
  std::mt19937_64 gen(5510);
  for (int e = -60; e <= 60; ++e) {
    for (int k = 0; k < 2000; ++k) {
      const double x = std::ldexp(static_cast<double>(gen() >> 11) * 0x1p-53, e);
      v.push_back(x);
      v.push_back(-x);
      const double h = std::floor(x) + 0.5;  // a half and its neighbours
      v.push_back(h);
      v.push_back(-h);
      v.push_back(std::nextafter(h, 0.0));
      v.push_back(std::nextafter(-h, 0.0));
      v.push_back(std::nextafter(h, 1e308));
    }
  }
  for (double x : v) {
    const double want = std::round(x);
    const double got = r::round(x);
    if (std::isnan(want)) {
      EXPECT_TRUE(std::isnan(got)) << x;
    } else {
      EXPECT_EQ(std::bit_cast<std::uint64_t>(got), std::bit_cast<std::uint64_t>(want))
          << std::hexfloat << x;
    }
    if (std::isfinite(x) && std::fabs(x) < 9.2e18) {
      EXPECT_EQ(r::llround(x), std::llround(x)) << std::hexfloat << x;
    }
  }
}

// A valve commanded open moves open += (1 - open) * step each ms until
// the step no longer changes it; from there FillingProcess skips the
// update (Valve::settled). With no flow variation, wander or fall time
// the load is the sum of what the open valve let through, computed here
// with the update every ms: the process must show it bit for bit over
// opening, settling, closing and reopening (fails when a valve counts as
// settled before its update stops changing it, or stays settled after a
// new opening).
TEST(PR5510Filling, SettledValveSkipsOnlyUpdatesThatChangeNothing) {
  plc::sim::FillingConfig c;
  c.flow_variation = 0.0;
  c.flow_wander = 0.0;
  c.fall_time_s = 0.0;  // a ring of one entry: what left the valve lands the next ms
  c.noise_kg = 0.0;
  c.impact_noise = 0.0;
  plc::sim::FillingProcess p(c);
  const double step = std::min(1.0, 0.001 / c.valve_time_s);
  double open = 0.0, in_ring = 0.0, load = 0.0;
  bool was_cmd = false;
  int settled_ms = 0;
  for (int ms = 0; ms < 7000; ++ms) {
    const bool cmd = ms < 3000 || (ms >= 3200 && ms < 6500);  // open, close, reopen
    if (cmd || was_cmd || open != 0.0) {
      const double before = open;
      open += ((cmd ? 1.0 : 0.0) - open) * step;
      if (!cmd && open < 1e-4) open = 0.0;
      settled_ms += cmd && open == before;
    }
    was_cmd = cmd;
    const double leaving = (open * 1.0 * c.coarse_rate + 0.0 * 1.0 * c.fine_rate) * 1.0 * 0.001;
    load += in_ring;
    in_ring = leaving;
    p.step_1ms(cmd, false, false);
    ASSERT_EQ(std::bit_cast<std::uint64_t>(p.load()), std::bit_cast<std::uint64_t>(load))
        << "ms " << ms;
  }
  EXPECT_GT(settled_ms, 2000);  // most of both open spells
}

// The discharge valve's rest (closed and staying closed: no move, no
// emptying) is kept as a bool, refreshed after each of its moves. With no
// flow in, the load is what the discharge left, computed here with the
// valve's update every ms while it is commanded or still open: the process
// must show it bit for bit over openings, the close-down tail (open
// decays below 1e-4) and long rests (fails when the rest is taken while
// the valve is still closing).
TEST(PR5510Filling, DischargeRestOnlyWhileClosed) {
  plc::sim::FillingConfig c;
  c.flow_variation = 0.0;
  c.flow_wander = 0.0;
  c.noise_kg = 0.0;
  c.impact_noise = 0.0;
  c.initial_load = 50.0;
  plc::sim::FillingProcess p(c);
  const double step = std::min(1.0, 0.001 / c.valve_time_s);
  double open = 0.0, load = c.initial_load;
  bool was_cmd = false;
  int moving_closed = 0;
  for (int ms = 0; ms < 6000; ++ms) {
    const bool cmd = (ms >= 100 && ms < 400) || (ms >= 2000 && ms < 2050) ||
                     (ms >= 2600 && ms < 2601) || (ms >= 4000 && ms < 4300);
    if (cmd || was_cmd || open != 0.0) {
      open += ((cmd ? 1.0 : 0.0) - open) * step;
      if (!cmd && open < 1e-4) open = 0.0;
      moving_closed += !cmd && open > 0.0;
      if (open > 0.0) load -= std::min(load, open * c.discharge_rate * 0.001);
    }
    was_cmd = cmd;
    p.step_1ms(false, false, cmd);
    ASSERT_EQ(std::bit_cast<std::uint64_t>(p.load()), std::bit_cast<std::uint64_t>(load))
        << "ms " << ms;
  }
  EXPECT_GT(moving_closed, 300);  // closing tails after each opening
  EXPECT_GT(load, 0.0);           // not all emptied: every opening counts
}

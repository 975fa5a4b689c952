// Safety functions and passivation of the simulated NORD device, seen
// through NORD_SAFE_IO (spec nord-profisafe.md §1.5, §2.8, §8.3, §8.4 item 6).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include "plc/fb/safety/f_host_diag.hpp"
#include "plc/fb/safety/nord_error_codes.hpp"
#include "safety_rig.hpp"

namespace {

using namespace safety_test;
using plc::safety::FHostState;
namespace diag = plc::safety::diag;
namespace err = plc::safety::nord::err;

// §1.5 / §2.8: SLS overspeed -> 5781, module passivation (P801 = 0); no
// ACK_REQ (OA refused) before 10 s after the error, even with the cause
// gone; then ACK_REI reintegrates.
TEST(SafetyNordFunctions, SlsViolationReintegratesOnlyAfter10s_Spec2_8) {
  Rig r;
  r.io.SLS = true;
  r.io.SLS_LEVEL = 1;  // P823[-02] = 500 rpm
  r.start();
  r.model->set_speed_rpm(400);
  r.scan(5);
  ASSERT_TRUE(r.running());
  EXPECT_TRUE(r.io.SLS_OK);
  EXPECT_EQ(r.io.SLS_LEVEL_ACT, 1);
  r.model->set_speed_rpm(600);
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, 10), 0);
  const plc::TIME t_err = r.ctx.now;
  r.model->set_speed_rpm(0);  // cause removed at once
  r.scan(5);
  EXPECT_TRUE(r.io.DIAG & diag::kDevFault);
  EXPECT_EQ(r.io.DIAG_CODE, err::kSlsViolated);
  while (r.ctx.now - t_err < std::chrono::milliseconds(9990)) {
    r.scan();
    ASSERT_FALSE(r.io.ACK_REQ) << "ACK_REQ before 10 s";
    ASSERT_TRUE(r.all_safe());
    if ((r.ctx.cycle % 1000) == 0) r.ack();  // refused before 10 s
  }
  ASSERT_GT(r.scan_until([&] { return r.io.ACK_REQ; }, 100), 0);
  EXPECT_GE(r.ctx.now - t_err, std::chrono::seconds(10));
  r.ack();
  EXPECT_GT(r.scan_until([&] { return r.running(); }, 10), 0);
}

// §1.5: SSM is a status bit only and never passivates, even with P801 = 0.
TEST(SafetyNordFunctions, SsmStatusOnlyNeverPassivates_Spec1_5) {
  Rig r;
  r.start();
  EXPECT_TRUE(r.io.SSM);
  r.model->set_speed_rpm(60);  // above max SSM 50
  r.scan(20);
  EXPECT_FALSE(r.io.SSM);
  EXPECT_TRUE(r.running());
  r.model->set_speed_rpm(-40);
  r.scan(3);
  EXPECT_TRUE(r.io.SSM);
}

// §8.3: SSR window, SDI-P direction, SOS window via the status bits and
// the errors 5782-5785.
TEST(SafetyNordFunctions, SsrWindowStatusAndViolation5782_Spec1_5) {
  Rig r(Params{{"p823_6", "100"}});  // min SSR 100, max SSR 2000
  r.model->set_speed_rpm(500);
  r.io.SSR = true;
  r.start();
  EXPECT_TRUE(r.io.SSR_OK);
  r.model->set_speed_rpm(50);
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, 10), 0);
  r.scan(3);
  EXPECT_EQ(r.io.DIAG_CODE, err::kSsrViolated);
}

TEST(SafetyNordFunctions, SdiPositiveTripsOnNegativeMovement5783_Spec1_5) {
  Rig r;
  r.io.SDI_P = true;
  r.start();
  r.model->set_speed_rpm(10);
  r.scan(5);
  EXPECT_TRUE(r.io.SDI_P_OK);
  // 2048 inc/rev: -10 rpm is about 341 inc/s; P824[-01] = 100 inc.
  r.model->set_speed_rpm(-10);
  const int n = r.scan_until([&] { return r.io.QBAD; }, 1000);
  ASSERT_GT(n, 250);  // ~293 ms of reverse movement needed
  r.scan(3);
  EXPECT_EQ(r.io.DIAG_CODE, err::kSdiPViolated);
}

TEST(SafetyNordFunctions, SosWindow5785_Spec1_5) {
  Rig r;
  r.io.SOS = true;
  r.start();
  EXPECT_TRUE(r.io.SOS_OK);
  r.model->set_position_inc(150);  // P824[-03] = 100 inc
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, 5), 0);
  r.scan(3);
  EXPECT_EQ(r.io.DIAG_CODE, err::kSosViolated);
}

// §1.5: a function requested in F-data while off in P820 -> 5756.. (q).
TEST(SafetyNordFunctions, FunctionRequestedWithoutP820_5756_Spec1_5) {
  Rig r(Params{{"p820_1", "0"}});
  r.start();
  r.io.SLS = true;
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, 5), 0);
  r.scan(3);
  EXPECT_EQ(r.io.DIAG_CODE, err::kSls);
  r.io.SLS = false;  // host passivated sends 0 anyway; request withdrawn
  r.scan(5);
  EXPECT_TRUE(r.io.ACK_REQ);
}

// §2.8 / §8.4 item 6: with P801 = 1 (channel passivation) a commanded but
// disabled SO2 (5742) switches only SO2 off; the module keeps running; the
// channel needs In 3.7 to come back after the cause is gone.
TEST(SafetyNordFunctions, ChannelPassivationNeedsIn3_7_Spec2_8) {
  Rig r(Params{{"p801", "1"}, {"p802_4", "0"}});
  r.start();
  ASSERT_TRUE(r.model->ossd(0));
  r.io.OSSD2 = true;
  r.scan(5);
  EXPECT_EQ(r.model->current_code(), err::kSo2NotEnabled);
  EXPECT_TRUE(r.running());  // no module passivation
  EXPECT_TRUE(r.model->ossd(0));
  EXPECT_FALSE(r.model->ossd(1));
  r.io.OSSD2 = false;  // cause gone, channel stays passivated (latched)
  r.scan(20);
  EXPECT_TRUE(r.running());
  r.io.CH_PASS_ACK = true;
  r.scan();
  r.io.CH_PASS_ACK = false;
  r.scan(3);
  EXPECT_EQ(r.model->previous_code(), err::kSo2NotEnabled);
  EXPECT_EQ(r.model->current_code(), 0);
}

// §2.8: with P801 = 1 an injected SO1 short (5732) passivates only SO1 and
// holds at least 10 s.
TEST(SafetyNordFunctions, ChannelPassivationOutputShortHolds10s_Spec5_5) {
  Rig r(Params{{"p801", "1"}});
  r.io.OSSD3 = true;
  r.start();
  r.model->inject_device_fault(err::kOutput1);
  r.scan(3);
  EXPECT_FALSE(r.model->ossd(0));
  EXPECT_TRUE(r.model->ossd(2));
  EXPECT_TRUE(r.running());
  r.model->clear_device_fault();
  r.io.CH_PASS_ACK = true;
  r.scan(5000);
  EXPECT_FALSE(r.model->ossd(0));  // < 10 s: error still active
  r.io.CH_PASS_ACK = false;
  r.scan(5100);
  r.io.CH_PASS_ACK = true;
  r.scan(3);
  r.io.CH_PASS_ACK = false;
  r.scan(3);
  EXPECT_TRUE(r.model->ossd(0));
}

// §5.5 ("the 4-digit code is sent to the F-host"; manual §8.4.2) with
// P801 = 1: a channel fault passivates only its channel and sets no
// Device_Fault, yet the program must see its code. DIAG_CODE shows 5742 and
// DIAG bit kDevCode says the device reports a code now; the error stays
// latched (and its code current) after the cause is gone until In 3.7
// acknowledges the channel (§2.8), then the bit drops and DIAG_CODE keeps
// the last code.
TEST(SafetyNordFunctions, ChannelPassivationCodeReachesProgram5742_Spec5_5) {
  Rig r(Params{{"p801", "1"}, {"p802_4", "0"}});
  r.start();
  ASSERT_EQ(r.io.DIAG_CODE, 0);
  r.io.OSSD2 = true;
  ASSERT_GT(r.scan_until([&] { return r.io.DIAG_CODE == err::kSo2NotEnabled; }, 250), 0);
  EXPECT_TRUE(r.io.DIAG & diag::kDevCode);
  EXPECT_FALSE(r.io.DIAG & diag::kDevFault);
  EXPECT_TRUE(r.running());
  r.io.OSSD2 = false;  // cause gone: the channel error stays latched
  r.scan(300);
  EXPECT_EQ(r.model->current_code(), err::kSo2NotEnabled);
  EXPECT_TRUE(r.io.DIAG & diag::kDevCode);
  r.io.CH_PASS_ACK = true;
  r.scan();
  r.io.CH_PASS_ACK = false;
  ASSERT_GT(r.scan_until([&] { return !(r.io.DIAG & diag::kDevCode); }, 250), 0);
  EXPECT_EQ(r.model->current_code(), 0);
  EXPECT_EQ(r.io.DIAG_CODE, err::kSo2NotEnabled);
  EXPECT_TRUE(r.running());
}

// §1.5 / §2.8 with P801 = 1: a safety-function violation is only reported
// (no passivation); the report is the code, so the program must see 5781.
TEST(SafetyNordFunctions, ReportOnlyViolationCodeReachesProgram5781_Spec5_5) {
  Rig r(Params{{"p801", "1"}});
  r.io.SLS = true;
  r.io.SLS_LEVEL = 1;  // P823[-02] = 500 rpm
  r.start();
  r.model->set_speed_rpm(600);
  ASSERT_GT(r.scan_until([&] { return r.io.DIAG_CODE == err::kSlsViolated; }, 250), 0);
  EXPECT_TRUE(r.io.DIAG & diag::kDevCode);
  EXPECT_TRUE(r.running());
}

// §5.5: a code that comes and goes between two diagnosis reads still reaches
// the program (the device counts its codes; the host then shows P842).
TEST(SafetyNordFunctions, ShortLivedChannelCodeReachesProgram_Spec5_5) {
  Rig r(Params{{"p801", "1"}, {"p802_4", "0"}});
  r.start();
  r.io.OSSD2 = true;
  r.scan();
  r.io.OSSD2 = false;
  r.io.CH_PASS_ACK = true;  // acknowledged at once: the code lives a few ms
  r.scan(3);
  r.io.CH_PASS_ACK = false;
  r.scan(3);
  ASSERT_EQ(r.model->current_code(), 0);
  ASSERT_EQ(r.model->previous_code(), err::kSo2NotEnabled);
  ASSERT_GT(r.scan_until([&] { return r.io.DIAG_CODE == err::kSo2NotEnabled; }, 250), 0);
  EXPECT_TRUE(r.running());
}

// §4.5 P803: SI1/SI2 dual channel apart longer than the discrepancy time ->
// 5731; clears when both are off.
TEST(SafetyNordFunctions, Discrepancy5731_Spec4_5) {
  Rig r(Params{{"p800_1", "1"}, {"p803", "20"}});
  r.start();
  r.model->set_si(true, false);
  r.scan(15);
  EXPECT_TRUE(r.running());  // within P803
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, 20), 0);
  r.scan(3);
  EXPECT_EQ(r.io.DIAG_CODE, err::kDiscrepancy);
  r.model->set_si(true, true);
  r.scan(20);
  EXPECT_FALSE(r.io.ACK_REQ);  // needs both channels off
  r.model->set_si(false, false);
  EXPECT_GT(r.scan_until([&] { return r.io.ACK_REQ; }, 10), 0);
}

// §8.4 item 8: while passivated the application sees 0 for every F-input
// (OSSDn_ON stays false though the raw inverted bits read 0 = "on").
TEST(SafetyNordFunctions, PassivatedInputsAreZero_Spec8_4_8) {
  Rig r;
  r.model->set_si(true, true);
  r.start();
  EXPECT_TRUE(r.io.SI1);
  r.model->inject_device_fault(err::kEncoder);
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, 5), 0);
  EXPECT_FALSE(r.io.SI1);
  EXPECT_FALSE(r.io.SI2);
  EXPECT_FALSE(r.io.OSSD1_OFF);
  EXPECT_FALSE(r.io.OSSD1_ON);
  EXPECT_FALSE(r.io.SSM);
}

}  // namespace

namespace {

// §4.5 P805: an SI level must be stable for the filter time before the
// device reports it; a shorter pulse is filtered out.
TEST(SafetyNordFunctions, InputFilterP805_Spec4_5) {
  Rig r(Params{{"p805", "20"}});
  r.start();
  r.model->set_si(true, false);
  r.scan(10);
  r.model->set_si(false, false);  // 10 ms pulse < 20 ms filter
  r.scan(40);
  EXPECT_FALSE(r.io.SI1);
  r.model->set_si(true, false);
  r.scan(15);
  EXPECT_FALSE(r.io.SI1);
  r.scan(10);
  EXPECT_TRUE(r.io.SI1);
}

// §4.5 P806 / §5.5 5737: SI1 assigned to clock 1 but fed from elsewhere ->
// 5737, module passivation, reintegration no sooner than 10 s.
TEST(SafetyNordFunctions, ClockMonitoringP806_5737Holds10s_Spec5_5) {
  Rig r(Params{{"p806_1", "1"}});
  r.model->set_si_source(0, 1);
  r.model->set_si(true, false);
  r.start();
  ASSERT_TRUE(r.running());
  EXPECT_TRUE(r.io.SI1);
  r.model->set_si_source(0, 0);  // now fed from static 24 V
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, 5), 0);
  const plc::TIME t_err = r.ctx.now;
  r.scan(3);
  EXPECT_EQ(r.io.DIAG_CODE, err::kInput1Diag);
  r.model->set_si_source(0, 1);  // wiring fixed at once
  ASSERT_GT(r.scan_until([&] { return r.io.ACK_REQ; }, 11000), 0);
  EXPECT_GE(r.ctx.now - t_err, std::chrono::seconds(10));
  r.ack();
  EXPECT_GT(r.scan_until([&] { return r.running(); }, 10), 0);
}

}  // namespace

namespace {

// §5.6: FE LED blink code of 5713 (the manual's Fig. 20 example): strobe
// 3 x 200/200 ms, 2 s off, tens 1 blink, units 3 blinks (1 s on / 1 s off).
TEST(SafetyNordFunctions, FeLedBlinkCode5713_Spec5_6) {
  using plc::sim::nord_fe_led;
  auto at = [](int ms) { return nord_fe_led(5713, std::chrono::milliseconds(ms)); };
  EXPECT_TRUE(at(0));
  EXPECT_FALSE(at(250));
  EXPECT_TRUE(at(450));
  EXPECT_TRUE(at(850));
  EXPECT_FALSE(at(1300));  // pause
  EXPECT_FALSE(at(3100));
  EXPECT_TRUE(at(3300));  // tens: 1 blink 3.2-4.2 s
  EXPECT_FALSE(at(4300));
  EXPECT_FALSE(at(6000));  // gap [AMBIG] 2 s
  EXPECT_TRUE(at(7300));   // units: blinks at 7.2, 9.2, 11.2 s
  EXPECT_TRUE(at(9300));
  EXPECT_TRUE(at(11300));
  EXPECT_FALSE(at(12300));
  EXPECT_FALSE(nord_fe_led(0, std::chrono::milliseconds(0)));
}

}  // namespace

namespace {

// The device status outputs as NORD_SAFE_IO has always computed them each
// scan (spec §2.4 bit map), from IN_DATA and QBAD.
void expect_status_outputs(const plc::safety::NORD_SAFE_IO& io, int scan) {
  namespace out = plc::safety::nord::out;
  std::uint8_t d[plc::safety::nord::kFDataBytes];
  for (std::size_t i = 0; i < plc::safety::nord::kFDataBytes; ++i) d[i] = io.FMOD.IN_DATA[i];
  auto get = [&d](plc::safety::nord::Bit b) { return plc::safety::nord::get(d, b); };
  SCOPED_TRACE(scan);
  ASSERT_EQ(io.OSSD1_OFF, get(out::kOssd1Off));
  ASSERT_EQ(io.OSSD2_OFF, get(out::kOssd2Off));
  ASSERT_EQ(io.OSSD3_OFF, get(out::kOssd3Off));
  ASSERT_EQ(io.CLOCK1_OFF, get(out::kClock1Off));
  ASSERT_EQ(io.CLOCK2_OFF, get(out::kClock2Off));
  ASSERT_EQ(io.OSSD1_ON, !io.QBAD && !get(out::kOssd1Off));
  ASSERT_EQ(io.OSSD2_ON, !io.QBAD && !get(out::kOssd2Off));
  ASSERT_EQ(io.OSSD3_ON, !io.QBAD && !get(out::kOssd3Off));
  ASSERT_EQ(io.SI1, get(out::kSi1));
  ASSERT_EQ(io.SI2, get(out::kSi2));
  ASSERT_EQ(io.SOS_OK, get(out::kSosOk));
  ASSERT_EQ(io.SLS_OK, get(out::kSlsOk));
  ASSERT_EQ(io.SLS_LEVEL_ACT, (get(out::kSlsLevel1) ? 2 : 0) | (get(out::kSlsLevel0) ? 1 : 0));
  ASSERT_EQ(io.SDI_P_OK, get(out::kSdiPOk));
  ASSERT_EQ(io.SDI_N_OK, get(out::kSdiNOk));
  ASSERT_EQ(io.SSM, get(out::kSsm));
  ASSERT_EQ(io.SSR_OK, get(out::kSsrOk));
}

}  // namespace

// The status outputs are decoded once per change of IN_DATA and QBAD and
// written every scan: over random commands, speeds, positions, device
// faults and silences (QBAD both ways, acknowledged), each scan's outputs
// are those of its F-data, also after a write between scans (debugger) to
// any of them.
TEST(SafetyNordFunctions, StatusOutputsFollowEveryScansFData_Spec2_4) {
  Rig r;
  r.start();
  Random rng{0x5DEECE66Dull};
  bool saw_qbad = false, saw_good = false, ack_req_prev = false;
  long resume_at = -1, clear_at = -1, ack_at = -1;
  for (int i = 0; i < 30000; ++i) {
    switch (rng.below(40)) {
      case 0:
        r.io.OSSD1 = !r.io.OSSD1;
        break;
      case 1:
        r.io.OSSD2 = !r.io.OSSD2;
        break;
      case 2:
        r.io.OSSD3 = !r.io.OSSD3;
        break;
      case 3:
        r.io.SLS = !r.io.SLS;
        r.io.SLS_LEVEL = static_cast<plc::USINT>(rng.below(4));
        break;
      case 4:
        r.io.SDI_P = !r.io.SDI_P;
        break;
      case 5:
        r.io.SDI_N = !r.io.SDI_N;
        break;
      case 6:
        r.io.SSR = !r.io.SSR;
        break;
      case 7:
        r.io.SOS = !r.io.SOS;
        break;
      case 8:
        r.model->set_speed_rpm(rng.below(1200) - 600);
        break;
      case 9:
        r.model->set_position_inc(rng.below(300));
        break;
      case 10:
        if (rng.below(20) == 0 && clear_at < 0) {
          r.model->inject_device_fault(err::kEncoder);
          clear_at = i + 1 + rng.below(300);
        }
        break;
      case 11:
        if (rng.below(20) == 0 && resume_at < 0) {
          r.model->stop(true);
          resume_at = i + 1 + rng.below(300);
        }
        break;
      case 12: {  // the debugger writes an output between scans
        plc::BOOL* outs[] = {&r.io.OSSD1_OFF, &r.io.OSSD2_ON, &r.io.SI1,       &r.io.SLS_OK,
                             &r.io.SSM,       &r.io.SSR_OK,   &r.io.CLOCK2_OFF};
        plc::BOOL* o = outs[rng.below(7)];
        *o = !*o;
        r.io.SLS_LEVEL_ACT = static_cast<plc::USINT>(rng.below(4));
        break;
      }
      default:
        break;
    }
    if (i == resume_at) {
      r.model->stop(false);
      resume_at = -1;
    }
    if (i == clear_at) {
      r.model->clear_device_fault();
      clear_at = -1;
    }
    if (r.io.ACK_REQ && !ack_req_prev) ack_at = i + rng.below(20);
    ack_req_prev = r.io.ACK_REQ;
    r.io.FMOD.ACK_REI = (i == ack_at);
    r.scan();
    (r.io.QBAD ? saw_qbad : saw_good) = true;
    expect_status_outputs(r.io, i);
    if (HasFatalFailure()) return;
  }
  EXPECT_TRUE(saw_qbad);
  EXPECT_TRUE(saw_good);

  // F-data 0 both good and passivated (all SOs on, 100 rpm: no SSM), so
  // only QBAD tells OSSDn_ON: the device falls silent and comes back.
  Rig q;
  q.io.OSSD1 = q.io.OSSD2 = q.io.OSSD3 = true;
  q.model->set_speed_rpm(100);
  int zero_good = 0, zero_bad = 0;
  for (int i = 0; i < 1500; ++i) {
    if (i == 300) q.model->stop(true);
    if (i == 600) q.model->stop(false);
    q.io.FMOD.ACK_REI = q.io.ACK_REQ && i % 2 == 0;
    q.scan();
    expect_status_outputs(q.io, i);
    if (HasFatalFailure()) return;
    const bool zero = q.io.FMOD.IN_DATA == std::array<plc::BYTE, 4>{};
    if (zero) ++(q.io.QBAD ? zero_bad : zero_good);
  }
  EXPECT_GT(zero_good, 100);
  EXPECT_GT(zero_bad, 100);
  EXPECT_TRUE(q.io.OSSD1_ON);
}

// NORD_SAFE_IO builds the F-data In once per change of its ten input bytes
// and ack_hold_ (issue 23): lockstep with a block that builds it every scan
// (scan_uncached), the same F-data, request PDUs and outputs in every scan,
// over random inputs (SLS_LEVEL 0..255), one-scan and held CH_PASS_ACK, and
// device silences that hold the acknowledge over several scans.
TEST(SafetyNordFunctions, FDataInCache_SameAsBuiltEveryScan_Spec2_3) {
  Rig cached, full;
  Random rng{0xCAC4Eull};
  int silent_left = 0, holds_past_pulse = 0, key_repeats = 0;
  std::array<plc::BYTE, 4> prev_out{};
  for (int i = 0; i < 60000; ++i) {
    const int what = rng.below(30);
    const int v = rng.below(256);
    bool stop = false;
    for (Rig* r : {&cached, &full}) {
      auto& io = r->io;
      switch (what) {
        case 0:
          io.OSSD1 = v & 1;
          break;
        case 1:
          io.OSSD2 = v & 1;
          break;
        case 2:
          io.OSSD3 = v & 1;
          break;
        case 3:
          io.SOS = v & 1;
          break;
        case 4:
          io.SLS = v & 1;
          break;
        case 5:
          io.SLS_LEVEL = static_cast<plc::USINT>(v & 3);
          break;
        case 6:
          io.SLS_LEVEL = static_cast<plc::USINT>(v);
          break;
        case 7:
          io.SDI_P = v & 1;
          break;
        case 8:
          io.SDI_N = v & 1;
          break;
        case 9:
          io.SSR = v & 1;
          break;
        case 10:
        case 11:
          io.CH_PASS_ACK = true;
          break;  // dropped again below
        case 12:
          stop = silent_left == 0 && (v & 7) == 0;
          break;
        default:
          io.CH_PASS_ACK = io.CH_PASS_ACK && (v & 3) != 0;
          break;
      }
      r->io.FMOD.ACK_REI = r->io.ACK_REQ && (i & 1);
    }
    if (stop) {
      silent_left = 1 + rng.below(150);
      for (Rig* r : {&cached, &full}) r->model->stop(true);
    } else if (silent_left > 0 && --silent_left == 0) {
      for (Rig* r : {&cached, &full}) r->model->stop(false);
    }
    cached.scan();
    full.ctx.now += full.dt;
    full.io.scan_uncached(full.ctx);
    full.dev->step(full.ctx.now, full.dt);
    ++full.ctx.cycle;
    ASSERT_EQ(cached.io.FMOD.OUT_DATA, full.io.FMOD.OUT_DATA) << "scan " << i;
    const auto a = cached.io.FMOD.port.out(), b = full.io.FMOD.port.out();
    ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << "scan " << i;
    ASSERT_EQ(cached.io.QBAD, full.io.QBAD) << "scan " << i;
    ASSERT_EQ(cached.io.OSSD1_ON, full.io.OSSD1_ON) << "scan " << i;
    ASSERT_EQ(cached.io.DIAG, full.io.DIAG) << "scan " << i;
    const bool ack_bit = (cached.io.FMOD.OUT_DATA[3] & 0x80) != 0;
    if (ack_bit && !cached.io.CH_PASS_ACK) ++holds_past_pulse;
    if (cached.io.FMOD.OUT_DATA == prev_out) ++key_repeats;
    prev_out = cached.io.FMOD.OUT_DATA;
  }
  EXPECT_GT(holds_past_pulse, 20);
  EXPECT_GT(key_repeats, 10000);
}

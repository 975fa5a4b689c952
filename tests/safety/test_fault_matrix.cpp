// Fault matrix, host <-> simulated NORD F-device (spec nord-profisafe.md §8.4).
// Every row: the fault is detected and told apart in DIAG, the module
// passivates within F_WD_Time plus one scan (virtual time, 1 ms scans,
// F_WD_Time 100 ms), outputs stay safe, and it reintegrates only as specified.
#include <gtest/gtest.h>

#include "plc/fb/safety/f_host_diag.hpp"
#include "plc/fb/safety/nord_error_codes.hpp"
#include "safety_rig.hpp"

namespace {

using namespace safety_test;
using plc::safety::FHostState;
namespace diag = plc::safety::diag;
namespace err = plc::safety::nord::err;

constexpr int kWdScans = 100;  // F_WD_Time / scan time

// Holds safe for `scans` without ACK, then needs a rising ACK_REI while
// ACK_REQ; returns to Run with SO1 back on.
void expect_ack_reintegration(Rig& r, int hold_scans = 300) {
  ASSERT_GT(r.scan_until([&] { return r.io.ACK_REQ; }, 2000), 0) << "ACK_REQ never raised";
  for (int i = 0; i < hold_scans; ++i) {
    r.scan();
    ASSERT_TRUE(r.all_safe()) << "not safe while waiting for ACK, scan " << i;
    ASSERT_TRUE(r.io.ACK_REQ);
  }
  r.ack();
  ASSERT_GT(r.scan_until([&] { return r.running(); }, 10), 0);
  r.scan(2);
  EXPECT_FALSE(r.model->fail_safe_active());
  EXPECT_EQ(r.model->ossd(0), r.io.OSSD1);
  EXPECT_EQ(r.model->ossd(1), r.io.OSSD2);
  EXPECT_EQ(r.io.DIAG, 0);
}

// §8.4 item 1: a response corrupted on the way to the host -> host CRC error.
TEST(SafetyFaultMatrix, ResponseCrcCorruption_HostDetects_Spec8_4_1) {
  Rig r;
  r.start();
  ASSERT_TRUE(r.running());
  r.model->corrupt_responses(1, 2, 0x04);
  const int n = r.scan_until([&] { return r.io.QBAD; }, kWdScans + 1);
  ASSERT_GT(n, 0);
  EXPECT_TRUE(r.io.DIAG & diag::kHostCrc);
  EXPECT_FALSE(r.io.DIAG & diag::kDevCeCrc);
  EXPECT_TRUE(r.io.PASS_OUT);
  r.scan(2);
  EXPECT_TRUE(r.all_safe());
  expect_ack_reintegration(r);
}

// §8.4 item 1: a request corrupted on the way to the device -> CE_CRC.
TEST(SafetyFaultMatrix, RequestCrcCorruption_DeviceReportsCeCrc_Spec8_4_1) {
  Rig r;
  r.start();
  r.model->corrupt_requests(1, 1, 0x10);
  const int n = r.scan_until([&] { return r.io.QBAD; }, kWdScans + 1);
  ASSERT_GT(n, 0);
  EXPECT_FALSE(r.model->ossd(0));  // device went safe at once
  EXPECT_TRUE(r.io.DIAG & diag::kDevCeCrc);
  EXPECT_FALSE(r.io.DIAG & diag::kHostCrc);
  EXPECT_EQ(r.model->crc_errors(), 1u);
  expect_ack_reintegration(r);
}

// §8.4 item 2: an old response replayed to the host fails CRC2 (other CN).
TEST(SafetyFaultMatrix, RepeatedResponse_StaleConsNr_Spec8_4_2) {
  Rig r;
  r.start();
  r.model->repeat_old_responses(1);
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, kWdScans + 1), 0);
  EXPECT_TRUE(r.io.DIAG & diag::kHostCrc);
  expect_ack_reintegration(r);
}

// §8.4 item 2: an old request replayed to the device is rejected and its
// data is not acted on.
TEST(SafetyFaultMatrix, RepeatedRequest_DeviceRejects_Spec8_4_2) {
  Rig r;
  r.io.OSSD1 = false;
  r.scan(10);
  ASSERT_TRUE(r.running());
  r.io.OSSD2 = true;
  r.scan(3);
  ASSERT_TRUE(r.model->ossd(1));
  r.model->repeat_old_requests(1);
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, kWdScans + 1), 0);
  EXPECT_TRUE(r.io.DIAG & diag::kDevCeCrc);
  EXPECT_TRUE(r.all_safe());
  expect_ack_reintegration(r);
}

// §8.4 item 4: a response computed with another CRC1 (another F-device or
// address pair) fails CRC2 at the host.
TEST(SafetyFaultMatrix, ForeignDeviceResponse_FailsCrc2_Spec8_4_4) {
  Rig r;
  r.start();
  r.model->answer_as_foreign_device(1);
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, kWdScans + 1), 0);
  EXPECT_TRUE(r.io.DIAG & diag::kHostCrc);
  expect_ack_reintegration(r);
}

// §8.4 item 3: the device stops answering -> host watchdog trips no later
// than F_WD_Time + one scan after the last valid telegram.
TEST(SafetyFaultMatrix, HostTimeout_DeviceSilent_Spec8_4_3) {
  Rig r;
  r.start();
  r.model->stop(true);
  const int n = r.scan_until([&] { return r.io.QBAD; }, 1000);
  ASSERT_GT(n, 0);
  EXPECT_LE(n, kWdScans + 2);  // last valid telegram was read one scan before the stop
  EXPECT_GE(n, kWdScans);      // and not before F_WD_Time
  EXPECT_TRUE(r.io.DIAG & diag::kHostWd);
  r.scan(50);
  EXPECT_TRUE(r.all_safe());
  EXPECT_FALSE(r.io.ACK_REQ);  // cause still present
  r.model->stop(false);
  expect_ack_reintegration(r);
}

// §8.4 item 3 boundary: responses delayed by less than F_WD_Time pass, by
// more they trip the host watchdog.
TEST(SafetyFaultMatrix, DelayedResponses_WatchdogBoundary_Spec8_4_3) {
  Rig r;
  r.start();
  r.model->delay_responses(90ms, 300ms);
  for (int i = 0; i < 400; ++i) {
    r.scan();
    ASSERT_NE(r.io.FMOD.STATE, FHostState::PassiveComm) << "tripped at " << i;
  }
  EXPECT_TRUE(r.running());
  r.model->delay_responses(120ms, 300ms);
  const int n = r.scan_until([&] { return r.io.QBAD; }, 1000);
  ASSERT_GT(n, 0);
  EXPECT_LE(n, kWdScans + 2);
  EXPECT_TRUE(r.io.DIAG & diag::kHostWd);
  expect_ack_reintegration(r);
}

// §8.4 item 3: the F-host stops (frozen scan) -> the device watchdog
// switches the outputs off within F_WD_Time + one step. When the host runs
// again, the device's answer waiting for it is 300 ms old: past F_WD_Time
// from the request, so the host trips its own watchdog (§2.7) and never
// hands that data to the program (before issue 9 it took it as valid).
TEST(SafetyFaultMatrix, DeviceTimeout_HostFrozen_Spec8_4_3) {
  Rig r;
  r.start();
  ASSERT_TRUE(r.model->ossd(0));
  int off_after = -1;
  for (int i = 1; i <= 300; ++i) {
    r.device_only(1);
    if (off_after < 0 && !r.model->ossd(0)) off_after = i;
  }
  ASSERT_GT(off_after, 0);
  EXPECT_LE(off_after, kWdScans + 1);
  EXPECT_GE(off_after, kWdScans);
  EXPECT_EQ(r.model->watchdog_expiries(), 1u);
  r.scan();
  EXPECT_TRUE(r.io.QBAD);
  EXPECT_TRUE(r.all_safe());
  EXPECT_TRUE(r.io.DIAG & diag::kHostWd);
  EXPECT_EQ(r.io.FMOD.protocol().late_answers(), 1u);
  expect_ack_reintegration(r);
}

// §8.4 item 3: requests lost on the way (device sees nothing new) -> both
// watchdogs; the device's outputs go off within F_WD_Time + one step.
TEST(SafetyFaultMatrix, DroppedRequests_DeviceWatchdog_Spec8_4_3) {
  Rig r;
  r.start();
  r.model->drop_requests(200ms);
  int off_after = -1;
  for (int i = 1; i <= 300 && off_after < 0; ++i) {
    r.scan();
    if (!r.model->ossd(0)) off_after = i;
  }
  ASSERT_GT(off_after, 0);
  EXPECT_LE(off_after, kWdScans + 2);
  EXPECT_GE(r.model->watchdog_expiries(), 1u);
  expect_ack_reintegration(r);
}

// §8.4 item 7 / §2.8: a device fault (q) passivates the module: Device_Fault,
// DIAG_CODE from the device's P841; ACK_REQ only after the cause is gone.
TEST(SafetyFaultMatrix, DeviceFault_Acknowledgeable_Spec8_4_7) {
  Rig r;
  r.start();
  r.model->inject_device_fault(err::kEncoder);
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, kWdScans + 1), 0);
  r.scan(5);
  EXPECT_TRUE(r.io.DIAG & diag::kDevFault);
  EXPECT_EQ(r.io.DIAG_CODE, err::kEncoder);
  EXPECT_EQ(r.io.FMOD.STATE, FHostState::PassiveDevice);
  EXPECT_TRUE(r.all_safe());
  // Acknowledge while ACK_REQ = 0 (cause present): ignored.
  r.ack();
  r.scan(100);
  EXPECT_TRUE(r.all_safe());
  EXPECT_FALSE(r.io.ACK_REQ);
  r.model->clear_device_fault();
  expect_ack_reintegration(r);
}

// §8.4 item 7: a fatal error is not cleared by OA, only by a power cycle.
TEST(SafetyFaultMatrix, DeviceFault_FatalLatchedUntilPowerCycle_Spec8_4_7) {
  Rig r;
  r.start();
  r.model->inject_device_fault(err::kTemperature, true);
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, kWdScans + 1), 0);
  for (int k = 0; k < 3; ++k) {
    r.ack();
    r.scan(500);
    EXPECT_TRUE(r.all_safe());
    EXPECT_FALSE(r.io.ACK_REQ);
  }
  EXPECT_EQ(r.io.DIAG_CODE, err::kTemperature);
  EXPECT_TRUE(r.model->fatal());
  r.model->power_cycle();
  EXPECT_FALSE(r.model->fatal());
  EXPECT_FALSE(r.model->fparams_ok());  // needs the F-parameters again
}

// §8.4 item 7: more than 15 system errors -> permanent 5792, even after a
// power cycle.
TEST(SafetyFaultMatrix, SystemErrorsAbove15ArePermanent_Spec2_8) {
  Rig r;
  for (int i = 0; i < 15; ++i) {
    r.model->inject_system_error();
    EXPECT_EQ(r.model->current_code(), err::kSystemError);
    r.model->power_cycle();
    EXPECT_FALSE(r.model->fatal());
  }
  r.model->inject_system_error();
  EXPECT_EQ(r.model->current_code(), err::kSystemErrorMax);
  r.model->power_cycle();
  EXPECT_TRUE(r.model->fatal());
  EXPECT_EQ(r.model->system_errors(), 16);
}

// Siemens F-I/O DB (anchors §4.4): ACK_REI only counts as a rising edge
// while ACK_REQ is set; a level held from before ACK_REQ does not count.
TEST(SafetyFaultMatrix, AcknowledgeWithAndWithoutAckReq_Anchors4_4) {
  Rig r;
  r.start();
  // Without ACK_REQ: an ACK_REI pulse in Run changes nothing.
  r.ack();
  EXPECT_TRUE(r.running());
  r.model->corrupt_responses(1, 0, 0x80);
  r.io.FMOD.ACK_REI = true;  // pressed before ACK_REQ and held
  ASSERT_GT(r.scan_until([&] { return r.io.ACK_REQ; }, 200), 0);
  r.scan(200);
  EXPECT_TRUE(r.io.ACK_REQ);
  EXPECT_TRUE(r.all_safe());
  r.io.FMOD.ACK_REI = false;
  r.scan();
  r.io.FMOD.ACK_REI = true;  // the rising edge while ACK_REQ
  ASSERT_GT(r.scan_until([&] { return r.running(); }, 10), 0);
  r.io.FMOD.ACK_REI = false;
}

// Siemens F-I/O DB (anchors §4.4): PASS_ON passivates (QBAD, not PASS_OUT)
// and the module reintegrates by itself when PASS_ON drops.
TEST(SafetyFaultMatrix, PassOnPassivatesWithoutPassOut_Anchors4_4) {
  Rig r;
  r.start();
  r.io.FMOD.PASS_ON = true;
  r.scan(3);
  EXPECT_TRUE(r.io.QBAD);
  EXPECT_FALSE(r.io.PASS_OUT);
  EXPECT_TRUE(r.all_safe());
  r.io.FMOD.PASS_ON = false;
  ASSERT_GT(r.scan_until([&] { return r.running(); }, 5), 0);
  r.scan(2);
  EXPECT_TRUE(r.model->ossd(0));
}

// ACK_NEC = 0: a device fault reintegrates without ACK_REI once the cause is
// gone; a communication fault still needs ACK_REI (anchors §4.4).
TEST(SafetyFaultMatrix, AckNecZeroAutoReintegratesDeviceFaultOnly_Anchors4_4) {
  Rig r;
  r.io.FMOD.ACK_NEC = false;
  r.start();
  r.model->inject_device_fault(err::kEncoder);
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, 10), 0);
  r.model->clear_device_fault();
  ASSERT_GT(r.scan_until([&] { return r.running(); }, 20), 0);
  r.model->corrupt_responses(1, 0, 0x01);
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, 10), 0);
  ASSERT_GT(r.scan_until([&] { return r.io.ACK_REQ; }, 20), 0);
  r.scan(100);
  EXPECT_TRUE(r.all_safe());
  r.ack();
  EXPECT_GT(r.scan_until([&] { return r.running(); }, 10), 0);
}

}  // namespace

namespace {

// §8.4 item 2: the consecutive number wraps from 0xFFFFFF to 1 (not 0) on
// both sides without a fault (about 16.8 million scans of virtual time).
TEST(SafetyFaultMatrix, ConsNrWrapsTo1WithoutFault_Spec8_4_2) {
  Rig r;
  r.start();
  ASSERT_TRUE(r.running());
  bool saw_max = false, wrapped = false;
  for (std::uint32_t i = 0; i < 0x1000010u && !wrapped; ++i) {
    r.scan();
    const std::uint32_t cn = r.io.FMOD.protocol().cons_nr();
    if (cn == 0xFFFFFFu) saw_max = true;
    if (saw_max && cn == 1u) wrapped = true;
    if (r.io.QBAD) FAIL() << "passivated at scan " << i << " cn " << cn;
  }
  EXPECT_TRUE(wrapped);
  r.scan(10);
  EXPECT_TRUE(r.running());
  EXPECT_EQ(r.model->cons_nr(), r.io.FMOD.protocol().cons_nr());
}

}  // namespace

namespace {

// §8.4 item 4 / §6.4: the device's F-address changed (DIP read at power-on):
// the F-host's parameters now carry the wrong F_Dest_Add -> 5711, no cyclic
// exchange. The host notices the lost device after three watchdog periods,
// parameterises again and reports the code.
TEST(SafetyFaultMatrix, WrongDeviceAddressAfterPowerCycle5711_Spec8_4_4) {
  Rig r;
  r.start();
  r.model->set_dip_address(5);
  r.model->power_cycle();
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, kWdScans + 1), 0);
  ASSERT_GT(r.scan_until([&] { return r.io.DIAG_CODE == err::kDestMismatch; }, 2000), 0);
  EXPECT_TRUE(r.io.DIAG & diag::kFParError);
  r.scan(2000);
  EXPECT_TRUE(r.all_safe());
  EXPECT_FALSE(r.model->fparams_ok());
}

// A power-cycled device loses its F-parameters: the host sends them again
// and, since this follows a communication fault, needs ACK_REI to run.
TEST(SafetyFaultMatrix, DevicePowerCycleReparameterisedThenNeedsAck_Spec8_2) {
  Rig r;
  r.start();
  r.model->power_cycle();
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, kWdScans + 1), 0);
  ASSERT_GT(r.scan_until([&] { return r.model->fparams_ok(); }, 1000), 0);
  expect_ack_reintegration(r);
}

}  // namespace

// The pure F-host protocol class, driven by a hand-written responder
// (spec nord-profisafe.md §2.5 control/status byte, §2.6 consecutive number,
// §2.7 watchdog, §8.2 per-cycle host algorithm).
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstring>
#include <random>
#include <type_traits>
#include <vector>

#include "plc/fb/safety/control_status_byte.hpp"
#include "plc/fb/safety/f_host_diag.hpp"
#include "plc/fb/safety/f_host_protocol.hpp"

namespace {

using namespace std::chrono_literals;
using namespace plc::safety;

constexpr std::uint16_t kCrc1 = 0x32CB;

struct Loop {
  FHostProtocol host;
  std::array<std::uint8_t, 8> req{}, resp{};
  std::array<std::uint8_t, 4> app_out{0x11, 0x22, 0x33, 0x44}, app_in{};
  FHostCommand cmd;
  plc::TIME now{};
  std::uint32_t dev_cn = 0;
  std::array<std::uint8_t, 4> dev_data{0xA1, 0x02, 0x03, 0x04};
  bool dev_fv = true;

  Loop() {
    host.configure(kCrc1, 4, 4, 100ms);
    host.start(now);
  }
  // Host cycle only.
  void host_cycle() {
    now += 1ms;
    host.cycle(now, resp, req, app_out, app_in, cmd);
  }
  // A well-behaved device answer to the current request.
  void answer() {
    const std::uint8_t control = req[4];
    dev_cn = (control & cb::kRConsNr) ? 0 : next_cons_nr(dev_cn);
    if (control & cb::kOaReq) dev_fv = false;
    std::uint8_t status = (control & cb::kToggleH) ? sb::kToggleD : 0;
    if (dev_fv || (control & cb::kActivateFv)) status |= sb::kFvActivated;
    if (control & cb::kRConsNr) status |= sb::kConsNrR;
    write_pdu(resp, dev_data, status, dev_cn, kCrc1);
  }
  void cycle() {
    host_cycle();
    answer();
  }
};

std::uint8_t resp_status(const Loop& l) { return (l.req[4] & cb::kToggleH) ? sb::kToggleD : 0; }

// §2.5 / §8.2 start-up: first request R_cons_nr + activate_FV + Toggle_h = 1
// with CN 0; then OA_Req; then Run with toggling Toggle_h and data.
TEST(SafetyHostProtocol, StartupControlByteSequence_Spec2_5_8_2) {
  Loop l;
  l.cycle();
  EXPECT_EQ(l.req[4], cb::kRConsNr | cb::kActivateFv | cb::kToggleH);
  EXPECT_TRUE(check_pdu(l.req, 4, 0, kCrc1));
  EXPECT_EQ(l.req[0], 0);  // fail-safe output data
  l.cycle();
  EXPECT_EQ(l.host.state(), FHostState::Reintegrating);
  EXPECT_EQ(l.req[4], cb::kOaReq);  // Toggle_h now 0, CN 1, no activate_FV
  EXPECT_TRUE(check_pdu(l.req, 4, 1, kCrc1));
  l.cycle();
  EXPECT_EQ(l.host.state(), FHostState::Run);
  EXPECT_EQ(l.req[4], cb::kToggleH);
  EXPECT_EQ(l.req[0], 0x11);  // application data from Run on
  EXPECT_TRUE(check_pdu(l.req, 4, 2, kCrc1));
  EXPECT_EQ(l.app_in[0], 0xA1);
  EXPECT_FALSE(l.host.qbad());
}

// §8.2 step 2: no new response (toggle unchanged) -> the request is not
// rebuilt, the last valid data stays, and after F_WD_Time the watchdog
// trips: not at WD, at the first scan past it. The request stays
// outstanding (issue 9: it is never given up); its answer, when it comes
// late, is not used, and only then does the R_cons_nr request go out.
TEST(SafetyHostProtocol, WatchdogTripsJustAfterFWdTime_Spec2_7) {
  Loop l;
  for (int i = 0; i < 5; ++i) l.cycle();
  ASSERT_EQ(l.host.state(), FHostState::Run);
  l.host_cycle();  // reads the last answer: the last valid telegram
  const auto req_before = l.req;
  for (int i = 1; i <= 100; ++i) {
    l.host_cycle();  // device silent
    ASSERT_EQ(l.host.state(), FHostState::Run) << i;
    ASSERT_EQ(l.req, req_before);
    ASSERT_EQ(l.app_in[0], 0xA1);
  }
  l.host_cycle();  // 101 ms after the last valid telegram
  EXPECT_EQ(l.host.state(), FHostState::PassiveComm);
  EXPECT_TRUE(l.host.diag() & diag::kHostWd);
  EXPECT_EQ(l.app_in[0], 0);
  for (int i = 0; i < 50; ++i) {
    l.host_cycle();
    ASSERT_EQ(l.req, req_before) << i;
  }
  l.dev_data[0] = 0xB7;  // the late answer, 151 ms after its request
  l.answer();
  l.host_cycle();
  EXPECT_EQ(l.host.late_answers(), 1u);
  EXPECT_EQ(l.app_in[0], 0);
  EXPECT_EQ(l.host.state(), FHostState::PassiveComm);
  // Now the reset: R_cons_nr, new toggle.
  EXPECT_TRUE(l.req[4] & cb::kRConsNr);
  EXPECT_NE(l.req[4] & cb::kToggleH, req_before[4] & cb::kToggleH);
}

// §2.1: IPAR_EN goes out as iPar_EN (CB bit 0); iPar_OK (SB bit 0) comes
// back as IPAR_OK.
TEST(SafetyHostProtocol, IparEnAndIparOk_Spec2_5) {
  Loop l;
  for (int i = 0; i < 4; ++i) l.cycle();
  l.cmd.ipar_en = true;
  l.host_cycle();
  EXPECT_TRUE(l.req[4] & cb::kIparEn);
  const std::uint8_t status = static_cast<std::uint8_t>(resp_status(l) | sb::kIparOk);
  l.dev_cn = next_cons_nr(l.dev_cn);
  write_pdu(l.resp, l.dev_data, status, l.dev_cn, kCrc1);
  l.host_cycle();
  EXPECT_TRUE(l.host.ipar_ok());
}

// §8.2 step 4: Device_Fault -> passivation; ACK_REQ once it clears.
TEST(SafetyHostProtocol, DeviceFaultThenAckReq_Spec8_2) {
  Loop l;
  for (int i = 0; i < 4; ++i) l.cycle();
  l.host_cycle();
  std::uint8_t st = static_cast<std::uint8_t>(((l.req[4] & cb::kToggleH) ? sb::kToggleD : 0) |
                                              sb::kDeviceFault | sb::kFvActivated);
  l.dev_cn = next_cons_nr(l.dev_cn);
  write_pdu(l.resp, l.dev_data, st, l.dev_cn, kCrc1);
  l.host_cycle();
  EXPECT_EQ(l.host.state(), FHostState::PassiveDevice);
  EXPECT_TRUE(l.host.diag() & diag::kDevFault);
  EXPECT_EQ(l.app_in[0], 0);
  l.dev_fv = true;
  l.answer();
  l.cycle();
  EXPECT_TRUE(l.host.ack_req());
  l.cmd.ack_rei = true;
  l.cycle();
  l.cmd.ack_rei = false;
  l.cycle();
  l.cycle();
  EXPECT_EQ(l.host.state(), FHostState::Run);
}

}  // namespace

namespace {

// §2.1: F-data above 12 bytes uses the 4-byte CRC2; the host builds and
// checks 13-byte PDUs (13 + 1 + 4 = 18 bytes) and rejects a corrupted one.
TEST(SafetyHostProtocol, FourByteCrcModuleOf13Bytes_Spec2_1) {
  FHostProtocol host;
  host.configure(kCrc1, 13, 13, 100ms);
  host.start({});
  std::array<std::uint8_t, 18> req{}, resp{};
  std::array<std::uint8_t, 13> out{}, in{}, dev{};
  for (int i = 0; i < 13; ++i) dev[i] = static_cast<std::uint8_t>(0xC0 + i);
  FHostCommand cmd;
  std::uint32_t cn = 0;
  plc::TIME now{};
  auto answer = [&] {
    cn = (req[13] & cb::kRConsNr) ? 0 : next_cons_nr(cn);
    const std::uint8_t st = (req[13] & cb::kToggleH) ? sb::kToggleD : 0;
    write_pdu(resp, dev, st, cn, kCrc1);
  };
  for (int i = 0; i < 4; ++i) {
    now += 1ms;
    host.cycle(now, resp, req, out, in, cmd);
    answer();
  }
  ASSERT_EQ(host.state(), FHostState::Run);
  EXPECT_EQ(in[12], 0xCC);
  EXPECT_TRUE(check_pdu(req, 13, host.cons_nr(), kCrc1));
  resp[15] ^= 0x01;  // a bit of the 4-byte CRC
  now += 1ms;
  host.cycle(now, resp, req, out, in, cmd);
  EXPECT_EQ(host.state(), FHostState::PassiveComm);
  EXPECT_EQ(in[12], 0);
}

}  // namespace

namespace {

// §8.2 step 4 / §2.5: a reset exchange is only complete when the device
// answers R_cons_nr without a communication error. A device that reports
// CE_CRC in its answer did not take the reset: the next request is R_cons_nr
// (number 0) again, not number 1.
TEST(SafetyHostProtocol, ResetAnsweredWithCeCrcIsRepeated_Spec8_2) {
  Loop l;
  l.host_cycle();
  ASSERT_TRUE(l.req[4] & cb::kRConsNr);
  const std::uint8_t st = static_cast<std::uint8_t>(resp_status(l) | sb::kCeCrc | sb::kFvActivated);
  write_pdu(l.resp, l.dev_data, st, 0, kCrc1);
  l.host_cycle();
  EXPECT_EQ(l.host.state(), FHostState::PassiveComm);
  EXPECT_TRUE(l.req[4] & cb::kRConsNr);
  EXPECT_EQ(l.host.cons_nr(), 0u);
}

}  // namespace

namespace {

// Siemens F-I/O DB (anchors §4.4): ACK_REI acknowledges an ACK_REQ the
// operator could see. A rising edge in the very scan the host would raise
// ACK_REQ (the answer to the reset arrives) does not count: otherwise OA_Req
// could ride on the first exchange after the reset (number 1), the one a
// repeated telegram from before the restart can match (issue 9).
TEST(SafetyHostProtocol, AckEdgeBeforeAckReqShownIgnored_Anchors4_4) {
  Loop l;
  for (int i = 0; i < 5; ++i) l.cycle();
  ASSERT_EQ(l.host.state(), FHostState::Run);
  l.host_cycle();
  l.answer();
  l.resp[0] ^= 0x01;  // corrupt answer -> host CRC error, reset request
  l.host_cycle();
  ASSERT_EQ(l.host.state(), FHostState::PassiveComm);
  ASSERT_TRUE(l.req[4] & cb::kRConsNr);
  l.answer();
  l.cmd.ack_rei = true;  // pressed in the scan that reads the reset answer
  l.host_cycle();
  EXPECT_EQ(l.host.state(), FHostState::WaitAck);
  EXPECT_FALSE(l.req[4] & cb::kOaReq);
  l.answer();
  l.host_cycle();  // held: no new edge
  EXPECT_EQ(l.host.state(), FHostState::WaitAck);
  l.cmd.ack_rei = false;
  l.answer();
  l.host_cycle();
  l.cmd.ack_rei = true;  // a real edge while ACK_REQ is shown
  l.answer();
  l.host_cycle();
  EXPECT_EQ(l.host.state(), FHostState::Reintegrating);
  EXPECT_TRUE(l.req[4] & cb::kOaReq);
  EXPECT_GE(l.host.cons_nr(), 2u);
}

// The F-host's steady path (cycle() in Run with a valid, in-time, fault-free
// answer) against the general path (cycle<false>()): two hosts fed the same
// telegrams, times and commands over a random walk of good answers, silences,
// watchdog trips, corrupted telegrams, status faults, FV_activated, iPar_OK
// and changing PASS_ON/ACK/IPAR_EN/output data give the same requests, the
// same application data and the same protocol state (every reflected field)
// after every scan. Fails with any step of the steady path left out or
// changed (e.g. the R_cons_nr reset, the toggle or ++deliveries).
struct StateBytes {
  std::vector<std::uint8_t> bytes;
  template <class T>
  void operator()(const char*, T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    bytes.insert(bytes.end(), b, b + sizeof(T));
  }
};
std::vector<std::uint8_t> state_bytes(FHostProtocol& h) {
  StateBytes s;
  h.reflect(s);
  return s.bytes;
}

TEST(SafetyHostProtocol, SteadyPathEqualsTheGeneralPath) {
  FHostProtocol fast, full;
  fast.configure(kCrc1, 4, 4, 100ms);
  full.configure(kCrc1, 4, 4, 100ms);
  plc::TIME now{};
  fast.start(now);
  full.start(now);
  std::array<std::uint8_t, 8> req_fast{}, req_full{}, resp{};
  std::array<std::uint8_t, 4> out{0x11, 0x22, 0x33, 0x44}, in_fast{}, in_full{};
  std::array<std::uint8_t, 4> dev_data{0xA1, 0x02, 0x03, 0x04};
  FHostCommand cmd;
  std::uint32_t dev_cn = 0;
  bool dev_fv = true;
  std::mt19937 rng(23);
  auto chance = [&](unsigned per_mille) { return rng() % 1000 < per_mille; };
  std::uint64_t steady = 0;
  for (int step = 0; step < 300000; ++step) {
    now += chance(5) ? std::chrono::milliseconds(40 + rng() % 80) : 1ms;
    if (chance(2)) cmd.pass_on = !cmd.pass_on;
    if (chance(20)) cmd.ack_rei = !cmd.ack_rei;
    if (chance(2)) cmd.ack_nec = !cmd.ack_nec;
    if (chance(3)) cmd.ipar_en = !cmd.ipar_en;
    if (chance(30)) out[rng() % 4] = static_cast<std::uint8_t>(rng());
    const bool was_run = fast.state() == FHostState::Run;
    fast.cycle<true, 4, 4>(now, resp, req_fast, out, in_fast, cmd);  // as F_MODULE<4, 4>
    full.cycle<false>(now, resp, req_full, out, in_full, cmd);
    ASSERT_EQ(req_fast, req_full) << step;
    ASSERT_EQ(in_fast, in_full) << step;
    ASSERT_EQ(state_bytes(fast), state_bytes(full)) << step;
    steady += was_run && fast.state() == FHostState::Run;
    // The device: mostly a good answer to the request, sometimes silent,
    // corrupt or reporting a fault.
    if (chance(30)) continue;  // silent this scan
    const std::uint8_t control = req_fast[4];
    dev_cn = (control & cb::kRConsNr) ? 0 : next_cons_nr(dev_cn);
    if (control & cb::kOaReq) dev_fv = false;
    std::uint8_t status = (control & cb::kToggleH) ? sb::kToggleD : 0;
    if (dev_fv || (control & cb::kActivateFv)) status |= sb::kFvActivated;
    if (control & cb::kRConsNr) status |= sb::kConsNrR;
    if (chance(2)) status |= sb::kCeCrc;
    if (chance(2)) status |= sb::kWdTimeout;
    if (chance(2)) status |= sb::kDeviceFault;
    if (chance(2)) status |= sb::kFvActivated;
    if (chance(100)) status |= sb::kIparOk;
    if (chance(30)) dev_data[rng() % 4] = static_cast<std::uint8_t>(rng());
    write_pdu(resp, dev_data, status, dev_cn, kCrc1);
    if (chance(3)) resp[rng() % 8] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
  }
  EXPECT_GT(steady, 50000u);  // the steady path did run
}

}  // namespace

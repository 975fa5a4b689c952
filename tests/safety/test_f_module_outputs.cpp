// F_MODULE's F-I/O DB outputs (STATE, PASS_OUT, QBAD, ACK_REQ, IPAR_OK,
// DIAG, VS_IN, VS_OUT) after every scan are what the protocol underneath
// says (FHostProtocol's state(), pass_out(), qbad(), ack_req(), ipar_ok(),
// diag(), data_valid(); DIAG bit kDevCode while the device reports a code;
// VS_OUT valid in Run without PASS_ON), also in the scans that take the
// steady exchange, for which F_MODULE writes them without reading the
// protocol back (issue 23). A random walk over PASS_ON, IPAR_EN, a report-
// only SLS violation (a device code in Run, P801 = 1), device faults,
// silences, acknowledgements and debugger writes to the outputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <type_traits>
#include <vector>

#include "plc/fb/safety/f_host_diag.hpp"
#include "plc/fb/safety/nord_error_codes.hpp"
#include "safety_rig.hpp"

namespace {

using namespace safety_test;
using plc::safety::FHostState;
namespace diag = plc::safety::diag;

::testing::AssertionResult outputs_follow_protocol(const plc::safety::NORD_SAFE_IO& io) {
  const auto& m = io.FMOD;
  const auto& p = m.protocol();
  const auto diag_want =
      static_cast<plc::BYTE>(p.diag() | (m.device_code() != 0 ? diag::kDevCode : 0));
  const std::uint8_t vs_in = p.data_valid() ? 0xFF : 0x00;
  const std::uint8_t vs_out = (p.state() == FHostState::Run && !m.PASS_ON) ? 0xFF : 0x00;
  auto fail = [](const char* what, int got, int want) {
    return ::testing::AssertionFailure() << what << " " << got << ", the protocol says " << want;
  };
  if (m.STATE != p.state())
    return fail("STATE", static_cast<int>(m.STATE), static_cast<int>(p.state()));
  if (m.PASS_OUT != p.pass_out()) return fail("PASS_OUT", m.PASS_OUT, p.pass_out());
  if (m.QBAD != p.qbad()) return fail("QBAD", m.QBAD, p.qbad());
  if (m.ACK_REQ != p.ack_req()) return fail("ACK_REQ", m.ACK_REQ, p.ack_req());
  if (m.IPAR_OK != p.ipar_ok()) return fail("IPAR_OK", m.IPAR_OK, p.ipar_ok());
  if (m.DIAG != diag_want) return fail("DIAG", m.DIAG, diag_want);
  for (auto b : m.VS_IN)
    if (b != vs_in) return fail("VS_IN", b, vs_in);
  for (auto b : m.VS_OUT)
    if (b != vs_out) return fail("VS_OUT", b, vs_out);
  return ::testing::AssertionSuccess();
}

TEST(FModuleOutputs, FollowTheProtocolEveryScan) {
  Rig r(Params{{"p801", "1"}});  // SLS violations report only: a code in Run
  r.start();
  Random rng{0xF00D5AFEull};
  bool ack_req_prev = false;
  long resume_at = -1, clear_at = -1, ack_at = -1;
  int run_with_code = 0, run_pass_on = 0, not_run = 0;
  for (int i = 0; i < 40000; ++i) {
    switch (rng.below(60)) {
      case 0:
        r.io.FMOD.PASS_ON = !r.io.FMOD.PASS_ON;
        break;
      case 1:
        r.io.FMOD.IPAR_EN = !r.io.FMOD.IPAR_EN;
        break;
      case 2:  // SLS level 1 (500 rpm) at 600 or 100 rpm: 5781 reported or not
        r.io.SLS = true;
        r.io.SLS_LEVEL = 1;
        r.model->set_speed_rpm(rng.below(2) ? 600 : 100);
        break;
      case 3:
        r.io.SLS = false;
        break;
      case 4:
        if (rng.below(10) == 0 && clear_at < 0) {
          r.model->inject_device_fault(plc::safety::nord::err::kEncoder);
          clear_at = i + 1 + rng.below(300);
        }
        break;
      case 5:
        if (rng.below(10) == 0 && resume_at < 0) {
          r.model->stop(true);
          resume_at = i + 1 + rng.below(400);
        }
        break;
      case 6: {  // the debugger writes the outputs between scans
        auto& m = r.io.FMOD;
        m.STATE = static_cast<FHostState>(rng.below(7));
        m.PASS_OUT = !m.PASS_OUT;
        m.QBAD = !m.QBAD;
        m.ACK_REQ = !m.ACK_REQ;
        m.IPAR_OK = !m.IPAR_OK;
        m.DIAG = static_cast<plc::BYTE>(rng.below(256));
        m.VS_IN[static_cast<std::size_t>(rng.below(4))] ^= 0x5A;
        m.VS_OUT[static_cast<std::size_t>(rng.below(4))] ^= 0xA5;
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
    ASSERT_TRUE(outputs_follow_protocol(r.io)) << "scan " << i;
    const auto& p = r.io.FMOD.protocol();
    if (p.state() != FHostState::Run) {
      ++not_run;
    } else {
      if (r.io.FMOD.device_code() != 0) ++run_with_code;
      if (r.io.FMOD.PASS_ON) ++run_pass_on;
    }
  }
  // The walk went where the steady exchange writes something that is not
  // a constant, and through the other states. (IPAR_OK: the simulated
  // device never sets iPar_OK; F_MODULE reads it back from the protocol in
  // every scan.)
  EXPECT_GT(run_with_code, 200);
  EXPECT_GT(run_pass_on, 200);
  EXPECT_GT(not_run, 200);
}

}  // namespace

namespace {

// FHostProtocol's reflected state as bytes (every field, in order).
struct ProtocolBytes {
  std::vector<std::uint8_t> bytes;
  template <class T>
  void operator()(const char*, T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    bytes.insert(bytes.end(), b, b + sizeof(T));
  }
};
std::vector<std::uint8_t> protocol_bytes(const plc::safety::FHostProtocol& p) {
  ProtocolBytes s;
  const_cast<plc::safety::FHostProtocol&>(p).reflect(s);
  return s.bytes;
}

// F_MODULE's operator() takes the steady scan on an inline path of its own
// (steady_exchange()) and every other scan through scan_general(), the
// whole block. Two modules on two devices, one scanned with operator(), one
// with scan_general() alone, fed the same random walk (PASS_ON, ACK_NEC,
// IPAR_EN, F-data, device faults, silences long enough for a restart,
// acknowledgements, debugger writes to the outputs), send the same
// telegrams, show the same outputs and keep the same protocol state after
// every scan. Fails with a step of the inline path left out (e.g. its
// diagnosis poll or the lost-device test).
TEST(FModuleOutputs, InlineSteadyScanEqualsScanGeneral) {
  Rig fast(Params{{"p801", "1"}}), general(Params{{"p801", "1"}});
  fast.io.OSSD1 = general.io.OSSD1 = true;
  Random rng{0x5CA9E11ull};
  long resume_at = -1, clear_at = -1;
  int inline_scans = 0, restarts = 0;
  for (int i = 0; i < 60000; ++i) {
    const int what = rng.below(80);
    const int v = rng.below(256);
    const int len = rng.below(500);
    if (what == 4 && clear_at < 0 && v < 40) clear_at = i + 1 + len;
    if (what == 5 && resume_at < 0 && v < 40) resume_at = i + 1 + len;
    for (Rig* r : {&fast, &general}) {
      auto& m = r->io.FMOD;
      switch (what) {
        case 0:
          m.PASS_ON = !m.PASS_ON;
          break;
        case 1:
          m.IPAR_EN = !m.IPAR_EN;
          break;
        case 2:
          m.ACK_NEC = !m.ACK_NEC;
          break;
        case 3:
          m.OUT_DATA[static_cast<std::size_t>(v & 3)] ^= static_cast<plc::BYTE>(1u << (v >> 5));
          break;
        case 4:
          if (clear_at == i + 1 + len)
            r->model->inject_device_fault(plc::safety::nord::err::kEncoder);
          break;
        case 5:
          if (resume_at == i + 1 + len) r->model->stop(true);
          break;
        case 6:  // the debugger writes outputs between scans
          m.STATE = static_cast<FHostState>(v % 7);
          m.QBAD = !m.QBAD;
          m.DIAG = static_cast<plc::BYTE>(v);
          m.VS_IN[static_cast<std::size_t>(v & 3)] ^= 0x5A;
          break;
        default:
          break;
      }
      if (i == resume_at) r->model->stop(false);
      if (i == clear_at) r->model->clear_device_fault();
      m.ACK_REI = m.ACK_REQ && (i & 1);
    }
    if (i == resume_at) resume_at = -1;
    if (i == clear_at) clear_at = -1;
    const auto deliveries = fast.io.FMOD.protocol().deliveries();
    const bool was_run = fast.io.FMOD.protocol().state() == FHostState::Run;
    const auto phase_restarts = fast.io.FMOD.protocol().watchdog_expiries_in_row();
    for (Rig* r : {&fast, &general}) {
      r->ctx.now += r->dt;
      if (r == &fast) {
        r->io.FMOD(r->ctx);
      } else {
        r->io.FMOD.scan_general(r->ctx);
      }
      r->dev->step(r->ctx.now, r->dt);
      ++r->ctx.cycle;
    }
    const auto& a = fast.io.FMOD;
    const auto& b = general.io.FMOD;
    ASSERT_TRUE(std::ranges::equal(a.port.out(), b.port.out())) << "scan " << i;
    ASSERT_EQ(a.IN_DATA, b.IN_DATA) << "scan " << i;
    ASSERT_EQ(a.VS_IN, b.VS_IN) << "scan " << i;
    ASSERT_EQ(a.VS_OUT, b.VS_OUT) << "scan " << i;
    ASSERT_EQ(a.STATE, b.STATE) << "scan " << i;
    ASSERT_EQ(a.PASS_OUT, b.PASS_OUT) << "scan " << i;
    ASSERT_EQ(a.QBAD, b.QBAD) << "scan " << i;
    ASSERT_EQ(a.ACK_REQ, b.ACK_REQ) << "scan " << i;
    ASSERT_EQ(a.IPAR_OK, b.IPAR_OK) << "scan " << i;
    ASSERT_EQ(a.DIAG, b.DIAG) << "scan " << i;
    ASSERT_EQ(a.DIAG_CODE, b.DIAG_CODE) << "scan " << i;
    ASSERT_EQ(a.device_code(), b.device_code()) << "scan " << i;
    ASSERT_EQ(protocol_bytes(a.protocol()), protocol_bytes(b.protocol())) << "scan " << i;
    if (was_run && a.protocol().state() == FHostState::Run &&
        a.protocol().deliveries() > deliveries)
      ++inline_scans;
    if (phase_restarts >= 3 && a.protocol().watchdog_expiries_in_row() == 0) ++restarts;
  }
  EXPECT_GT(inline_scans, 8000);  // the inline path ran
  EXPECT_GT(restarts, 2);         // and the lost-device restart happened
}

}  // namespace

// Randomized soak in virtual time (issue 9 acceptance): NORD_SAFE_IO against
// the simulated NORD F-device, 1,000,000 scans of 1 ms (F_WD_Time 100 ms)
// with random faults: corruption and repetition in both directions, lost
// requests, masquerade (a foreign CRC1), response delays on both sides of
// the watchdog time (0-300 ms, for 50-1500 ms, order kept as on a fieldbus),
// silence, device faults and device power cycles (restarts with new
// F-parameters), random PASS_ON, and quick operator acknowledgements (half
// of them in the first scan ACK_REQ is shown).
//
// Measured from the telegrams, not from the host: every frame the device
// sends carries a tag with the time its telegram was produced and the F-data
// the device meant (NordFrameTag). A value handed to the program (a step of
// FHostProtocol::deliveries()) is
//   * stale   if its source telegram is older than F_WD_Time at delivery,
//   * corrupt if it differs from what the device meant, or its telegram was
//             corrupted, foreign or not the one the host took it for.
// Also checked every scan: while QBAD every F-input is 0; while not, the
// inputs are the last delivered value; an OSSD is on at the device only if
// the device's last accepted request is the one the host built for that
// consecutive number and commands it.
//
// PLC_SAFETY_SOAK_SCANS=<n> runs n scans instead (e.g. longer runs, or
// shorter ones under sanitizers).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <unordered_map>

#include "plc/fb/safety/nord_error_codes.hpp"
#include "safety_rig.hpp"

namespace {

using namespace safety_test;
namespace err = plc::safety::nord::err;

long soak_scans() {
  const char* e = std::getenv("PLC_SAFETY_SOAK_SCANS");
  const long n = e ? std::strtol(e, nullptr, 10) : 0;
  return n > 0 ? n : 1'000'000;
}

enum Fault : int {
  kCorruptResp,
  kCorruptReq,
  kRepeatResp,
  kRepeatReq,
  kForeign,
  kDelayShort,  // delay <= F_WD_Time
  kDelayLong,   // delay > F_WD_Time
  kLoss,
  kSilence,
  kDeviceFault,
  kPowerCycle,
  kFaultKinds
};
constexpr const char* kFaultNames[kFaultKinds] = {
    "corrupt_resp", "corrupt_req", "repeat_resp", "repeat_req", "masquerade", "delay<=wd",
    "delay>wd",     "loss",        "silence",     "dev_fault",  "power_cycle"};

std::int64_t ms(plc::TIME t) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(t).count();
}

TEST(SafetySoak, MillionScansNoStaleNoCorruptValueReachesProgram_Spec2_7_8_4) {
  const long scans = soak_scans();
  const plc::TIME wd = 100ms;
  Rig r;
  Random rng{0x9E3779B97F4A7C15ull};
  std::unordered_map<std::uint32_t, std::array<std::uint8_t, 4>> host_sent;
  host_sent.reserve(1 << 16);

  long next_fault = 2000, resume_at = -1, clear_fault_at = -1, ack_at = -1;
  std::array<std::uint64_t, kFaultKinds> faults{};
  std::uint64_t passivations = 0, reintegrations = 0, delivered = 0, stale = 0, corrupt = 0;
  std::int64_t max_age = 0, max_held_age = 0;
  bool was_bad = true, ack_req_prev = false;
  std::uint32_t last_host_cn = 0xFFFFFFFFu;
  bool last_toggle = false;
  plc::sim::NordFrameTag in_inputs{};  // tag of the frame in the host's input bytes
  plc::sim::NordFrameTag last_value{};
  std::uint64_t deliveries_before = 0;

  for (long i = 0; i < scans; ++i) {
    // Random process: outputs, inputs and speed (SSM flips around 50 rpm).
    if (rng.below(8) == 0) {
      r.io.OSSD1 = rng.below(2);
      r.io.OSSD2 = rng.below(2);
      r.io.OSSD3 = rng.below(2);
    }
    if (rng.below(4) == 0) r.model->set_si(rng.below(2), rng.below(2));
    if (rng.below(16) == 0) r.model->set_speed_rpm(rng.below(100));
    // The user passivates now and then (PASS_ON, ~1 % of the time).
    if (rng.below(5000) == 0) r.io.FMOD.PASS_ON = true;
    if (r.io.FMOD.PASS_ON && rng.below(50) == 0) r.io.FMOD.PASS_ON = false;

    if (i == next_fault) {
      next_fault = i + 200 + rng.below(3000);
      const int n = 1 + rng.below(3);
      const std::size_t byte = static_cast<std::size_t>(rng.below(8));
      const auto mask = static_cast<std::uint8_t>(1u << rng.below(8));
      const int kind = rng.below(kFaultKinds);
      switch (kind) {
        case kCorruptResp:
          r.model->corrupt_responses(n, byte, mask);
          break;
        case kCorruptReq:
          r.model->corrupt_requests(n, byte, mask);
          break;
        case kRepeatResp:
          r.model->repeat_old_responses(n);
          break;
        case kRepeatReq:
          r.model->repeat_old_requests(n);
          break;
        case kForeign:
          r.model->answer_as_foreign_device(n);
          break;
        case kDelayShort:
        case kDelayLong: {
          const int d = kind == kDelayShort ? rng.below(101) : 101 + rng.below(200);
          r.model->delay_responses(std::chrono::milliseconds(d),
                                   std::chrono::milliseconds(50 + rng.below(1451)));
          break;
        }
        case kLoss:
          r.model->drop_requests(std::chrono::milliseconds(rng.below(200)));
          break;
        case kSilence:
          r.model->stop(true);
          resume_at = i + 1 + rng.below(300);
          break;
        case kDeviceFault:
          r.model->inject_device_fault(err::kEncoder);
          clear_fault_at = i + 1 + rng.below(500);
          break;
        default:
          r.model->power_cycle();
          break;
      }
      ++faults[kind];
    }
    if (i == resume_at) r.model->stop(false);
    if (i == clear_fault_at) r.model->clear_device_fault();
    // Operators acknowledge quickly: half at once, the rest within 50 scans.
    if (r.io.ACK_REQ && !ack_req_prev) ack_at = rng.below(2) ? i : i + rng.below(50);
    ack_req_prev = r.io.ACK_REQ;
    r.io.FMOD.ACK_REI = (i == ack_at);

    const plc::sim::NordFrameTag read_now = in_inputs;  // what this scan's host reads
    r.scan();
    if (r.model->answering()) in_inputs = r.model->shown_frame();

    // Record the request the host built this scan (clean, before any
    // injection on the device side), keyed by its consecutive number.
    const auto& proto = r.io.FMOD.protocol();
    const bool tog = (r.dev->outputs()[4] & 0x20) != 0;
    if (proto.cons_nr() != last_host_cn || tog != last_toggle) {
      last_host_cn = proto.cons_nr();
      last_toggle = tog;
      std::array<std::uint8_t, 4> d{};
      for (int k = 0; k < 4; ++k) d[k] = r.dev->outputs()[k];
      host_sent[last_host_cn] = d;
    }

    // A value handed to the program this scan: measure it by its telegram.
    const std::array<std::uint8_t, 4> in = {r.io.FMOD.IN_DATA[0], r.io.FMOD.IN_DATA[1],
                                            r.io.FMOD.IN_DATA[2], r.io.FMOD.IN_DATA[3]};
    if (proto.deliveries() != deliveries_before) {
      deliveries_before = proto.deliveries();
      ++delivered;
      const std::int64_t age = ms(r.ctx.now - read_now.produced);
      max_age = std::max(max_age, age);
      if (r.ctx.now - read_now.produced > wd) ++stale;
      if (read_now.corrupted || read_now.foreign || in != read_now.data) ++corrupt;
      last_value = read_now;
    }
    if (!r.io.QBAD) {
      ASSERT_EQ(in, last_value.data) << "scan " << i;
      max_held_age = std::max(max_held_age, ms(r.ctx.now - last_value.produced));
    } else {
      for (int k = 0; k < 4; ++k) ASSERT_EQ(in[k], 0) << "scan " << i;
    }
    // The device acts only on what the host built.
    if (r.model->ossd(0) || r.model->ossd(1) || r.model->ossd(2)) {
      std::array<std::uint8_t, 4> acc{};
      ASSERT_TRUE(r.model->accepted_request(r.model->cons_nr(), acc)) << "scan " << i;
      auto it = host_sent.find(r.model->cons_nr());
      ASSERT_NE(it, host_sent.end()) << "scan " << i;
      ASSERT_EQ(acc, it->second) << "scan " << i;
      if (r.model->ossd(0)) {
        ASSERT_TRUE(acc[0] & 0x01) << "scan " << i;
      }
      if (r.model->ossd(1)) {
        ASSERT_TRUE(acc[3] & 0x01) << "scan " << i;
      }
      if (r.model->ossd(2)) {
        ASSERT_TRUE(acc[3] & 0x02) << "scan " << i;
      }
    }
    if (r.io.QBAD && !was_bad) ++passivations;
    if (!r.io.QBAD && was_bad) ++reintegrations;
    was_bad = r.io.QBAD;
  }

  const auto& proto = r.io.FMOD.protocol();
  std::uint64_t injected = 0;
  std::printf("soak: %ld scans, faults injected:", scans);
  for (int k = 0; k < kFaultKinds; ++k) {
    std::printf(" %s %llu", kFaultNames[k], static_cast<unsigned long long>(faults[k]));
    injected += faults[k];
  }
  std::printf(" (total %llu)\n", static_cast<unsigned long long>(injected));
  std::printf(
      "soak: %llu values delivered, %llu stale, %llu corrupt; max age at delivery %lld ms, "
      "max age while held %lld ms (F_WD_Time %lld ms)\n",
      static_cast<unsigned long long>(delivered), static_cast<unsigned long long>(stale),
      static_cast<unsigned long long>(corrupt), static_cast<long long>(max_age),
      static_cast<long long>(max_held_age), static_cast<long long>(ms(wd)));
  std::printf(
      "soak: %llu passivations, %llu reintegrations; host: %llu CRC errors, %llu watchdog "
      "expiries, %llu late answers drained\n",
      static_cast<unsigned long long>(passivations),
      static_cast<unsigned long long>(reintegrations),
      static_cast<unsigned long long>(proto.crc_errors()),
      static_cast<unsigned long long>(proto.watchdog_expiries()),
      static_cast<unsigned long long>(proto.late_answers()));
  RecordProperty("scans", static_cast<int>(scans));
  RecordProperty("delivered", static_cast<int>(delivered));
  RecordProperty("stale", static_cast<int>(stale));
  RecordProperty("corrupt", static_cast<int>(corrupt));

  EXPECT_EQ(stale, 0u);
  EXPECT_EQ(corrupt, 0u);
  EXPECT_LE(max_age, ms(wd));
  // The soak must have exercised the paths it claims to.
  const auto per = static_cast<std::uint64_t>(scans / 100'000);  // 10 for 10^6
  for (int k = 0; k < kFaultKinds; ++k) EXPECT_GE(faults[k], 2 * per) << kFaultNames[k];
  EXPECT_GT(passivations, 30 * per);
  EXPECT_GT(reintegrations, 30 * per);
  EXPECT_GT(proto.late_answers(), per);
  EXPECT_GT(delivered, static_cast<std::uint64_t>(scans / 4));
}

}  // namespace

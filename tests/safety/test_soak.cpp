// Randomized soak in virtual time (issue acceptance): 1,000,000 scans of
// NORD_SAFE_IO against the simulated NORD F-device with random faults in
// both directions (corruption, replay, foreign CRC1, delays, lost requests,
// silence, device faults), random PASS_ON and random operator
// acknowledgements.
//
// Invariants checked every scan:
//  1. F-host: while QBAD = 0, the F-input data the application sees is
//     exactly the data the device sent in its (clean) response with the
//     consecutive number the host accepted: no corrupted, replayed or foreign
//     telegram's data ever reaches the block's outputs.
//  2. While QBAD = 1 every F-input is 0.
//  3. F-device: an OSSD is on only if the device's last accepted request is
//     the one the host built for that consecutive number and commands it.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <unordered_map>

#include "plc/fb/safety/nord_error_codes.hpp"
#include "safety_rig.hpp"

namespace {

using namespace safety_test;
namespace err = plc::safety::nord::err;

struct XorShift {
  std::uint64_t s;
  std::uint64_t next() {
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    return s;
  }
  int below(int n) { return static_cast<int>(next() % static_cast<std::uint64_t>(n)); }
};

TEST(SafetySoak, MillionScansRandomFaultsNoBadDataReachesOutputs) {
  constexpr int kScans = 1'000'000;
  Rig r;
  XorShift rng{0x9E3779B97F4A7C15ull};
  std::unordered_map<std::uint32_t, std::array<std::uint8_t, 4>> host_sent;
  host_sent.reserve(1 << 21);

  int next_fault = 2000, resume_at = -1, clear_fault_at = -1, ack_at = -1;
  std::uint64_t faults = 0, passivations = 0, reintegrations = 0, data_checks = 0;
  bool was_bad = true;
  std::uint32_t last_host_cn = 0xFFFFFFFFu;
  bool last_toggle = false;

  for (int i = 0; i < kScans; ++i) {
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
      ++faults;
      next_fault = i + 200 + rng.below(3000);
      const int n = 1 + rng.below(3);
      const std::size_t byte = static_cast<std::size_t>(rng.below(8));
      const auto mask = static_cast<std::uint8_t>(1u << rng.below(8));
      switch (rng.below(9)) {
        case 0:
          r.model->corrupt_responses(n, byte, mask);
          break;
        case 1:
          r.model->corrupt_requests(n, byte, mask);
          break;
        case 2:
          r.model->repeat_old_responses(n);
          break;
        case 3:
          r.model->repeat_old_requests(n);
          break;
        case 4:
          r.model->answer_as_foreign_device(n);
          break;
        case 5:
          r.model->delay_responses(std::chrono::milliseconds(rng.below(200)));
          break;
        case 6:
          r.model->drop_requests(std::chrono::milliseconds(rng.below(200)));
          break;
        case 7:
          r.model->stop(true);
          resume_at = i + 1 + rng.below(300);
          break;
        default:
          r.model->inject_device_fault(err::kEncoder);
          clear_fault_at = i + 1 + rng.below(500);
          break;
      }
    }
    if (i == resume_at) r.model->stop(false);
    if (i == clear_fault_at) r.model->clear_device_fault();
    if (r.io.ACK_REQ && ack_at < 0) ack_at = i + rng.below(50);
    r.io.FMOD.ACK_REI = (i == ack_at);
    if (i == ack_at) ack_at = -1;

    r.scan();

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

    // Invariants 1 and 2.
    if (!r.io.QBAD) {
      std::array<std::uint8_t, 4> sent{};
      ASSERT_TRUE(r.model->sent_data(proto.accepted_cons_nr(), sent)) << "scan " << i;
      for (int k = 0; k < 4; ++k)
        ASSERT_EQ(r.io.FMOD.IN_DATA[k], sent[k]) << "scan " << i << " byte " << k;
      ++data_checks;
    } else {
      for (int k = 0; k < 4; ++k) ASSERT_EQ(r.io.FMOD.IN_DATA[k], 0) << "scan " << i;
    }
    // Invariant 3.
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
  // The soak must have exercised the paths it claims to.
  EXPECT_GT(faults, 300u);
  EXPECT_GT(passivations, 200u);
  EXPECT_GT(reintegrations, 200u);
  EXPECT_GT(data_checks, kScans / 2u);
  RecordProperty("faults", static_cast<int>(faults));
  RecordProperty("passivations", static_cast<int>(passivations));
  std::printf("soak: %llu faults, %llu passivations, %llu reintegrations, %llu data checks\n",
              static_cast<unsigned long long>(faults),
              static_cast<unsigned long long>(passivations),
              static_cast<unsigned long long>(reintegrations),
              static_cast<unsigned long long>(data_checks));
}

}  // namespace

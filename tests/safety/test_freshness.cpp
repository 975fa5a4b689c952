// The watchdog promise of PROFIsafe (spec nord-profisafe.md §2.7, §8.2 step
// 2, §8.4 item 3): no process data older than F_WD_Time reaches the program,
// whatever the channel does with the delay, and also across a restart of the
// exchange (R_cons_nr) with a quick operator acknowledgement.
//
// The F-host protocol runs against a well-behaved device written here, over a
// device -> host channel that delays every telegram but keeps their order
// (a real fieldbus delivers cyclic frames in order; it only holds them back
// or skips superseded ones). Each device telegram carries the virtual time
// it was produced as its F-data, so the age of what the host hands over is
// measured from the telegram itself, not from anything the host believes.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>

#include "plc/fb/safety/control_status_byte.hpp"
#include "plc/fb/safety/f_host_protocol.hpp"
#include "safety_rig.hpp"

namespace {

using namespace std::chrono_literals;
using namespace plc::safety;
using safety_test::Random;

constexpr std::uint16_t kCrc1 = 0x32CB;
constexpr plc::TIME kWd = 100ms;

std::int64_t ms(plc::TIME t) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(t).count();
}

// A device that answers every new request at once, with its production time
// (ms, big-endian) as F-data, and reintegrates on OA_Req.
struct Device {
  std::uint32_t cn = 0;
  bool last_toggle = false;
  bool fault_fv = true;
  bool ce_crc = false;
  // Returns true and fills `out` when it produced a new telegram.
  bool step(plc::TIME now, const std::array<std::uint8_t, 8>& req,
            std::array<std::uint8_t, 8>& out) {
    const std::uint8_t control = req[4];
    const bool toggle = (control & cb::kToggleH) != 0;
    if (toggle == last_toggle) return false;
    last_toggle = toggle;
    const bool rcons = (control & cb::kRConsNr) != 0;
    cn = rcons ? 0 : next_cons_nr(cn);
    if (!check_pdu(req, 4, cn, kCrc1)) {
      ce_crc = true;
      fault_fv = true;
    } else if (rcons) {
      ce_crc = false;
    }
    if ((control & cb::kOaReq) && !ce_crc) fault_fv = false;
    const bool fv = fault_fv || ce_crc || (control & cb::kActivateFv);
    std::uint8_t status = toggle ? sb::kToggleD : 0;
    if (fv) status |= sb::kFvActivated;
    if (ce_crc) status |= sb::kCeCrc;
    if (rcons && !ce_crc) status |= sb::kConsNrR;
    const auto t = static_cast<std::uint32_t>(ms(now));
    std::array<std::uint8_t, 4> d{};
    if (!fv)
      d = {static_cast<std::uint8_t>(t >> 24), static_cast<std::uint8_t>(t >> 16),
           static_cast<std::uint8_t>(t >> 8), static_cast<std::uint8_t>(t)};
    write_pdu(out, d, status, cn, kCrc1);
    return true;
  }
};

// Device -> host channel: frames arrive in the order they were sent, each no
// sooner than its delay after it was sent; the host sees the newest arrived.
struct FifoChannel {
  struct InFlight {
    plc::TIME arrive;
    std::array<std::uint8_t, 8> pdu;
  };
  std::deque<InFlight> q;
  plc::TIME last_arrival{};
  void send(plc::TIME now, plc::TIME delay, const std::array<std::uint8_t, 8>& pdu) {
    const plc::TIME a = std::max(now + delay, last_arrival);
    last_arrival = a;
    q.push_back({a, pdu});
  }
  void deliver(plc::TIME now, std::array<std::uint8_t, 8>& seen) {
    while (!q.empty() && q.front().arrive <= now) {
      seen = q.front().pdu;
      q.pop_front();
    }
  }
};

struct Figures {
  std::uint64_t deliveries = 0, stale = 0, restarts = 0;
  std::int64_t max_age_ms = 0;
  std::int64_t first_ack_req_ms = -1;  // when ACK_REQ was first raised
};

// Runs `scans` 1 ms host cycles with delays drawn by `delay_of`; the operator
// acknowledges in the first scan ACK_REQ is shown.
template <class DelayOf>
Figures run(int scans, std::uint64_t seed, DelayOf delay_of) {
  FHostProtocol host;
  host.configure(kCrc1, 4, 4, kWd);
  host.start({});
  Device dev;
  FifoChannel ch;
  Random rng{seed};
  std::array<std::uint8_t, 8> req{}, seen{}, produced{};
  std::array<std::uint8_t, 4> out{0x01, 0, 0, 0}, in{};
  FHostCommand cmd;
  plc::TIME now{};
  Figures f;
  std::int64_t last_data = -1;
  FHostState prev = host.state();
  for (int i = 0; i < scans; ++i) {
    now += 1ms;
    ch.deliver(now, seen);
    cmd.ack_rei = host.ack_req();
    if (host.ack_req() && f.first_ack_req_ms < 0) f.first_ack_req_ms = ms(now);
    host.cycle(now, seen, req, out, in, cmd);
    if (host.state() == FHostState::PassiveComm && prev != FHostState::PassiveComm) ++f.restarts;
    prev = host.state();
    if (host.data_valid()) {
      const std::int64_t t = (std::int64_t{in[0]} << 24) | (in[1] << 16) | (in[2] << 8) | in[3];
      if (t != last_data) {  // a new value handed to the program
        ++f.deliveries;
        const std::int64_t age = ms(now) - t;
        f.max_age_ms = std::max(f.max_age_ms, age);
        if (age > ms(kWd)) ++f.stale;
        last_data = t;
      }
    }
    if (dev.step(now, req, produced)) ch.send(now, delay_of(rng, now), produced);
  }
  return f;
}

// Prints the figures; many values handed over, none older than F_WD_Time.
void expect_fresh(const Figures& f) {
  std::printf("freshness: %llu deliveries, %llu stale, max age %lld ms, %llu restarts\n",
              static_cast<unsigned long long>(f.deliveries),
              static_cast<unsigned long long>(f.stale), static_cast<long long>(f.max_age_ms),
              static_cast<unsigned long long>(f.restarts));
  EXPECT_GT(f.deliveries, 1000u);
  EXPECT_EQ(f.stale, 0u);
  EXPECT_LE(f.max_age_ms, ms(kWd));
}

// The pattern: replies delayed 110-190 ms (F_WD_Time 100 ms) in
// bursts, fast in between, quick acknowledgements. Before the fix a late
// genuine reply from before a restart matched the restarted sequence
// (same consecutive number and toggle, valid CRC2) and the host went from
// Reintegrating to Run with data up to 190 ms old.
TEST(SafetyFreshness, NoDataOlderThanFWdTime_DelaysStraddlingWatchdog_Spec2_7) {
  const Figures f = run(200'000, 0x51A7Eull, [](Random& rng, plc::TIME now) {
    const bool burst = (ms(now) / 700) % 2 == 1;  // 700 ms slow, 700 ms fast
    return burst ? plc::TIME(std::chrono::milliseconds(110 + rng.below(81)))
                 : plc::TIME(std::chrono::milliseconds(rng.below(20)));
  });
  expect_fresh(f);
  EXPECT_GT(f.restarts, 50u);
}

// Every delay from 0 to 3 x F_WD_Time, drawn per telegram.
TEST(SafetyFreshness, NoDataOlderThanFWdTime_AnyDelayUpTo3Wd_Spec2_7) {
  const Figures f = run(200'000, 0xDE1A7ull, [](Random& rng, plc::TIME) {
    return plc::TIME(std::chrono::milliseconds(rng.below(4) == 0 ? rng.below(301) : rng.below(60)));
  });
  expect_fresh(f);
}

// §8.2 step 8: ACK_REQ only once the exchange is healthy again. While every
// answer comes later than F_WD_Time (150 ms for the first 2 s) the reset
// exchange never completes in time, so there is nothing to acknowledge and
// no data; once the delay drops to 5 ms the host restarts, asks for the
// acknowledgement, and runs on fresh data.
TEST(SafetyFreshness, AckReqOnlyAfterHealthyExchange_Spec8_2) {
  const Figures f = run(4000, 1, [](Random&, plc::TIME now) {
    return now < plc::TIME(2s) ? plc::TIME(150ms) : plc::TIME(5ms);
  });
  EXPECT_GT(f.first_ack_req_ms, 2000);
  EXPECT_GT(f.deliveries, 100u);
  EXPECT_EQ(f.stale, 0u);
}

}  // namespace

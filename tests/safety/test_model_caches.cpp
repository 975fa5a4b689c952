// The simulated NORD F-device keeps parts of its per-step work from one
// change of their inputs to the next (issue 23): the q-error causes and the
// response's F-data Out (spec §2.4 table, nord_fdata_bits.hpp). Over many
// random steps (SI levels and clock sources, speeds, host requests, faults,
// power cycles, several i-parameter sets) what it keeps must be what it
// would compute in full from its state at that moment (spec
// nord-profisafe.md §8.3, q errors §1.5 / §2.8 / §4.5). Its response
// channel writes a frame that arrives at once straight where the shown one
// lives (push_delivered()): the host must see what push() and deliver()
// show (spec §8.4 item 3, delayed responses keep their order).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <limits>

#include "plc/fb/safety/control_status_byte.hpp"
#include "plc/fb/safety/f_parameters.hpp"
#include "plc/fb/safety/safety_pdu.hpp"
#include "plc/sim/nord_response_channel.hpp"
#include "safety_rig.hpp"

namespace {

using safety_test::Params;
using safety_test::Random;
using safety_test::Rig;

// Counts the scans at which some q error had a cause and at which the
// response carried F-data other than the fail-safe 0.
int random_walk(Rig& r, Random& rnd, int scans, int& with_data, int& with_so) {
  int with_cause = 0;
  with_data = with_so = 0;
  r.start();
  for (int i = 0; i < scans; ++i) {
    switch (rnd.below(40)) {
      case 0:
        r.model->set_si(rnd.below(2) != 0, rnd.below(2) != 0);
        break;
      case 1:
        r.model->set_si_source(rnd.below(2), rnd.below(3));
        break;
      case 2:
        // Mostly below every limit (a violation holds its q error 10 s).
        r.model->set_speed_rpm(rnd.below(8) == 0 ? rnd.below(2400) - 1200 : rnd.below(80) - 40);
        break;
      case 3:
        r.io.OSSD1 = rnd.below(2) != 0;
        r.io.OSSD2 = rnd.below(2) != 0;
        r.io.OSSD3 = rnd.below(2) != 0;
        break;
      case 4:
        r.io.SOS = rnd.below(4) == 0;
        r.io.SLS = rnd.below(3) == 0;
        r.io.SLS_LEVEL = static_cast<plc::USINT>(rnd.below(4));
        r.io.SDI_P = rnd.below(4) == 0;
        r.io.SDI_N = rnd.below(4) == 0;
        r.io.SSR = rnd.below(4) == 0;
        break;
      case 5:
        r.io.CH_PASS_ACK = !r.io.CH_PASS_ACK;
        break;
      case 6:
        r.io.FMOD.ACK_REI = !r.io.FMOD.ACK_REI;
        break;
      case 7:
        if (rnd.below(8) == 0) r.model->inject_device_fault(5732 + rnd.below(4));
        break;
      case 8:
        r.model->clear_device_fault();
        break;
      case 9:
        if (rnd.below(20) == 0) r.model->power_cycle();
        break;
      case 10:
        if (rnd.below(16) == 0) r.model->corrupt_requests(1, rnd.below(8), 0x10);
        break;
      default:
        break;
    }
    // Acknowledge now and then, so that the walk also spends long spells
    // in Run with process data.
    if (r.io.ACK_REQ && rnd.below(3) == 0) r.ack();
    r.scan(1 + rnd.below(3));
    const std::uint32_t full = r.model->q_causes_full();
    EXPECT_EQ(r.model->q_causes_kept(), full) << "scan " << i;
    if (r.model->q_causes_kept() != full) return with_cause;
    with_cause += full != 0;
    const std::array<std::uint8_t, 4> data = r.model->response_data_full();
    EXPECT_EQ(r.model->response_data(), data) << "scan " << i;
    if (r.model->response_data() != data) return with_cause;
    const std::array<bool, 3> so = r.model->ossd_full();
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(r.model->ossd(k), so[k]) << "SO" << k + 1 << ", scan " << i;
    if (so != std::array<bool, 3>{r.model->ossd(0), r.model->ossd(1), r.model->ossd(2)})
      return with_cause;
    with_so += so != std::array<bool, 3>{};
    with_data += data != std::array<std::uint8_t, 4>{};
  }
  return with_cause;
}

TEST(SafetyModelCaches, KeptCausesAndResponseDataAreTheFullOnesOverRandomSteps_Spec8_3) {
  const Params sets[] = {
      {},
      {{"p806_1", "1"}, {"p806_2", "2"}, {"p802_2", "0"}},
      {{"p801", "1"}, {"p802_1", "0"}, {"p802_4", "0"}, {"p806_2", "1"}, {"p800_1", "1"}},
      {{"p820_2", "0"}, {"p820_5", "0"}, {"p802_5", "0"}, {"p805", "2"}},
      {{"p800_2", "1"}, {"p801", "1"}, {"p802_4", "0"}},  // SO1/SO2 dual channel
  };
  std::uint64_t seed = 2300;
  int with_cause = 0, with_data = 0, with_so = 0;  // over all sets: the walk reaches each
  for (const Params& p : sets) {
    Rig r(p);
    Random rnd(++seed);
    int data = 0, so = 0;
    with_cause += random_walk(r, rnd, 30000, data, so);
    with_data += data;
    EXPECT_GT(so, 10);  // some SO on in every set
    with_so += so;
    EXPECT_FALSE(r.model->fatal());
  }
  EXPECT_GT(with_cause, 20000);
  EXPECT_GT(with_data, 3000);
  EXPECT_GT(with_so, 2000);
}

// evaluate() skips a step at rest (at_rest_: no function enabled, no q
// error or cause, SI at their filtered levels, pas_ and the request's
// F-data as the last full evaluate() left them). A twin device without the
// skip (set_rest_skip(false)) gets the same host, the same calls and the
// same steps; after every scan both must show the same bytes to the host
// and the same state (spec nord-profisafe.md §8.3 safety logic each cycle,
// §2.4 F-data Out). Fails when a call that changes what evaluate() reads
// leaves at_rest_ set (e.g. set_speed_rpm(): SSM, set_si(): SI1/SI2), or
// when a full evaluate() leaves build_response()'s kept F-data and status
// bits (resp_fresh_) as they were.
// The random changes both twin tests below make (the same draws, so each
// test's sequence is what it was): SI inputs, speed, OSSD/SOS/SLS, the
// channel-passivation acknowledgement, device faults, host stalls, the
// position, a fatal error with a later power cycle. Other `what` values
// are each test's own.
void common_random_change(Rig* r, int what, int x, int y) {
  switch (what) {
    case 0:
      r->model->set_si((x & 1) != 0, (x & 2) != 0);
      break;
    case 1:
      r->model->set_si_source(x & 1, (y % 3));
      break;
    case 2:
      r->model->set_speed_rpm((x & 7) == 0 ? y - 2048 : (y % 120) - 60);
      break;
    case 3:
      r->io.OSSD1 = (x & 1) != 0;
      r->io.OSSD2 = (x & 2) != 0;
      r->io.OSSD3 = (x & 4) != 0;
      break;
    case 4:
      r->io.SOS = (x & 3) == 0;
      r->io.SLS = (y & 3) == 0;
      r->io.SLS_LEVEL = static_cast<plc::USINT>(x >> 10);
      break;
    case 5:
      r->io.CH_PASS_ACK = !r->io.CH_PASS_ACK;
      break;
    case 6:
      if ((x & 7) == 0) r->model->inject_device_fault(5732 + (y & 3));
      break;
    case 7:
      r->model->clear_device_fault();
      break;
    case 10:
      if ((x & 63) == 0) r->device_only(50 + (y & 127));  // the host stalls: watchdog
      break;
    case 11:
      if ((x & 63) == 0) r->model->set_position_inc(y);
      break;
    case 12:
      if ((x & 255) == 0) {  // a fatal error, then a power cycle later
        r->model->inject_system_error();
        r->scan(1 + (y & 31));
        r->model->power_cycle();
      }
      break;
    default:
      break;
  }
}

TEST(SafetyModelCaches, RestSkipShowsWhatTheFullEvaluateShows_Spec8_3) {
  const Params none_enabled = {
      {"p820_1", "0"}, {"p820_2", "0"}, {"p820_3", "0"}, {"p820_4", "0"}, {"p820_5", "0"}};
  auto with = [&none_enabled](Params extra) {
    Params p = none_enabled;
    for (auto& [k, v] : extra) p[k] = v;
    return p;
  };
  const Params sets[] = {
      none_enabled,
      with({{"p805", "3"}, {"p806_1", "1"}, {"p802_2", "0"}}),
      with({{"p800_1", "1"}, {"p803", "5"}, {"p801", "1"}, {"p802_4", "0"}}),
      with({{"p800_2", "1"}, {"p801", "1"}, {"p823_7", "10"}}),
      {},  // every function enabled: never at rest, the twins still agree
  };
  std::uint64_t seed = 2330;
  long at_rest_like = 0;
  for (const Params& p : sets) {
    Rig a(p), b(p);
    b.model->set_rest_skip(false);
    Random rnd(++seed);
    a.start();
    b.start();
    for (int i = 0; i < 40000; ++i) {
      const int what = rnd.below(60);
      const int x = rnd.below(4096);
      const int y = rnd.below(4096);
      for (Rig* r : {&a, &b}) {
        switch (what) {
          case 8:
            if ((x & 31) == 0) r->model->power_cycle();
            break;
          case 9:
            if ((x & 15) == 0) r->model->corrupt_requests(1, y & 7, 0x10);
            break;
          default:
            common_random_change(r, what, x, y);
            break;
        }
        if (r->io.ACK_REQ && (y & 3) == 0) r->ack();
        r->scan(1 + (x % 3));
      }
      const auto ia = a.dev->inputs(), ib = b.dev->inputs();
      ASSERT_TRUE(std::equal(ia.begin(), ia.end(), ib.begin(), ib.end())) << "scan " << i;
      ASSERT_EQ(a.model->response_data(), b.model->response_data()) << "scan " << i;
      ASSERT_EQ(a.model->response_data(), a.model->response_data_full()) << "scan " << i;
      for (int k = 0; k < 3; ++k) ASSERT_EQ(a.model->ossd(k), b.model->ossd(k)) << "scan " << i;
      ASSERT_EQ(a.model->functions().ssm(), b.model->functions().ssm()) << "scan " << i;
      ASSERT_EQ(a.model->fail_safe_active(), b.model->fail_safe_active()) << "scan " << i;
      ASSERT_EQ(a.model->device_fault(), b.model->device_fault()) << "scan " << i;
      ASSERT_EQ(a.model->current_code(), b.model->current_code()) << "scan " << i;
      ASSERT_EQ(a.model->previous_code(), b.model->previous_code()) << "scan " << i;
      ASSERT_EQ(a.model->q_causes_kept(), b.model->q_causes_kept()) << "scan " << i;
      ASSERT_EQ(a.model->crc_errors(), b.model->crc_errors()) << "scan " << i;
      ASSERT_EQ(a.model->watchdog_expiries(), b.model->watchdog_expiries()) << "scan " << i;
      ASSERT_EQ(a.model->shown_frame().id, b.model->shown_frame().id) << "scan " << i;
      ASSERT_EQ(a.model->shown_frame().data, b.model->shown_frame().data) << "scan " << i;
      // Steps where the skip may apply: in Run, nothing active.
      at_rest_like += !a.model->fail_safe_active() && a.model->q_causes_kept() == 0 &&
                      !a.model->functions().monitoring(0);
    }
  }
  EXPECT_GT(at_rest_like, 20000);
}

// step() takes the steady exchange (step_steady(): a request that repeats
// the last accepted one but for Toggle_h, the number and CRC2, answered
// without the full handle_request() / evaluate() / build_response()) only
// where the full path gives the same. A twin without it
// (set_steady_path(false)) gets the same host, calls, injections, delays,
// dropped requests, stalls, power cycles (a new F-parameter block) and
// steps; after every scan both show the same bytes to the host and the
// same exchange state (spec nord-profisafe.md §8.3 cyclic exchange, §8.4
// injections). Fails when the steady path is taken after a call that
// changes what it assumes (e.g. an injection, a fault) or writes any
// byte, number or history entry other than the full path.
TEST(SafetyModelCaches, SteadyExchangeShowsWhatTheFullStepShows_Spec8_3) {
  const Params none_enabled = {
      {"p820_1", "0"}, {"p820_2", "0"}, {"p820_3", "0"}, {"p820_4", "0"}, {"p820_5", "0"}};
  auto with = [&none_enabled](Params extra) {
    Params p = none_enabled;
    for (auto& [k, v] : extra) p[k] = v;
    return p;
  };
  const Params sets[] = {
      none_enabled,
      with({{"p805", "3"}, {"p806_1", "1"}, {"p802_2", "0"}}),
      with({{"p800_1", "1"}, {"p803", "5"}, {"p801", "1"}, {"p802_4", "0"}}),
      {},  // every function enabled: never at rest, never steady
  };
  std::uint64_t seed = 2370;
  std::uint64_t steady = 0;
  for (const Params& p : sets) {
    Rig a(p), b(p);
    b.model->set_steady_path(false);
    Random rnd(++seed);
    a.start();
    b.start();
    for (int i = 0; i < 40000; ++i) {
      const int what = rnd.below(90);
      const int x = rnd.below(4096);
      const int y = rnd.below(4096);
      for (Rig* r : {&a, &b}) {
        switch (what) {
          case 8:
            if ((x & 7) == 0) r->model->power_cycle();
            break;
          case 9:
            if ((x & 255) == 0) r->model->corrupt_requests(1, y & 7, 0x10);
            break;
          case 13:
            if ((x & 31) == 0)
              r->model->delay_responses(std::chrono::milliseconds(1 + (y & 7)),
                                        std::chrono::milliseconds(y & 63));
            break;
          case 14:
            if ((x & 31) == 0) r->model->drop_requests(std::chrono::milliseconds(1 + (y & 15)));
            break;
          case 15:
            if ((x & 255) == 0) r->model->repeat_old_responses(1 + (y & 1));
            break;
          case 16:
            if ((x & 255) == 0) r->model->repeat_old_requests(1);
            break;
          case 17:
            if ((x & 255) == 0) r->model->answer_as_foreign_device(1);
            break;
          case 18:
            if ((x & 255) == 0) r->model->corrupt_responses(1, y & 7, 0x01);
            break;
          case 19:
            r->io.FMOD.ACK_REI = !r->io.FMOD.ACK_REI;
            break;
          default:
            common_random_change(r, what, x, y);
            break;
        }
        if (r->io.ACK_REQ && (y & 3) == 0) r->ack();
        r->scan(1 + (x % 3));
      }
      const auto ia = a.dev->inputs(), ib = b.dev->inputs();
      ASSERT_TRUE(std::equal(ia.begin(), ia.end(), ib.begin(), ib.end())) << "scan " << i;
      ASSERT_TRUE(a.model->same_exchange_state(*b.model)) << "scan " << i;
      ASSERT_EQ(a.model->cons_nr(), b.model->cons_nr()) << "scan " << i;
      ASSERT_EQ(a.model->fail_safe_active(), b.model->fail_safe_active()) << "scan " << i;
      ASSERT_EQ(a.model->current_code(), b.model->current_code()) << "scan " << i;
      ASSERT_EQ(a.model->q_causes_kept(), b.model->q_causes_kept()) << "scan " << i;
    }
    EXPECT_EQ(b.model->steady_steps(), 0u);
    std::printf("steady steps: %llu\n", static_cast<unsigned long long>(a.model->steady_steps()));
    steady += a.model->steady_steps();
  }
  EXPECT_GT(steady, 20000u);
}

// Two channels get the same frames, delays and deliveries; one takes each
// frame that step() delivers at once through push_delivered(), the other
// through push(). The frame shown, its tag and the frames in flight must
// agree after every delivery.
TEST(SafetyModelCaches, ChannelPushDeliveredShowsWhatPushAndDeliverShow_Spec8_4) {
  using plc::sim::NordFrameTag;
  using plc::sim::NordResponseChannel;
  using std::chrono::milliseconds;
  NordResponseChannel direct, ring;
  Random rnd(2311);
  plc::TIME now{};
  std::uint64_t id = 0;
  int at_once = 0, delayed = 0;
  for (int i = 0; i < 200000; ++i) {
    now += milliseconds(1);
    if (rnd.below(500) == 0) {  // a delay episode (sometimes none: 0 ms)
      const auto d = milliseconds(rnd.below(4) == 0 ? 0 : 1 + rnd.below(30));
      const auto how_long = milliseconds(rnd.below(200));
      direct.delay(d, how_long);
      ring.delay(d, how_long);
    }
    NordResponseChannel::Pdu pdu{};
    for (auto& b : pdu) b = static_cast<std::uint8_t>(rnd.below(256));
    NordFrameTag tag;
    tag.id = ++id;
    tag.sent = tag.produced = now;
    tag.data = {pdu[0], pdu[1], pdu[2], pdu[3]};
    tag.repeated = rnd.below(2) != 0;
    if (rnd.below(1000) == 0) {  // power_cycle()'s frame: sent, delivered a step later
      direct.send(now, pdu, tag);
      ring.send(now, pdu, tag);
      continue;
    }
    if (rnd.below(4) != 0) {  // the device answers this step
      const bool none_in_flight = ring.in_flight() == 0;
      NordResponseChannel::Frame& a = direct.push_delivered(now);
      a.pdu = pdu;
      a.tag = tag;
      NordResponseChannel::Frame& b = ring.push(now);
      b.pdu = pdu;
      b.tag = tag;
      (none_in_flight ? at_once : delayed)++;
    }
    direct.deliver(now);
    ring.deliver(now);
    ASSERT_EQ(direct.shown(), ring.shown()) << "step " << i;
    ASSERT_EQ(direct.shown_tag().id, ring.shown_tag().id) << "step " << i;
    ASSERT_EQ(direct.shown_tag().produced, ring.shown_tag().produced) << "step " << i;
    ASSERT_EQ(direct.in_flight(), ring.in_flight()) << "step " << i;
  }
  EXPECT_GT(at_once, 50000);
  EXPECT_GT(delayed, 10000);
}

// The device checks each new request's CRC2 and seals its response with
// Z4 kept per head (F-data and control/status byte, per toggle value) and
// the number's TAIL looked up once per exchange (CRC2 is linear,
// crc2_cache.hpp). Requests from a few heads (so the kept ones are hit)
// and now and then others, some with a wrong CRC2, a few with R_cons_nr
// (numbers up to some thousands: the upper bytes' TAIL changes too);
// new F-parameter blocks with other CRC1 seeds, power cycles and foreign
// responses between them. Each response must carry compute_crc2() of its
// bytes for the number the host expects (spec nord-profisafe.md §8.3
// cyclic 1-3, safety_pdu.hpp byte order), and the device must count a CRC
// error exactly for the wrong ones. Fails when a kept head outlives a
// change of CRC1 or its key misses a byte.
TEST(SafetyModelCaches, RequestCheckAndResponseCrc2AreComputeCrc2_Spec8_3) {
  namespace ps = plc::safety;
  plc::io::ModelParams mp;
  for (auto& [k, v] : safety_test::default_device_params()) mp.set(k, v);
  plc::sim::NordProfisafeModel m(mp);
  Random rnd(2317);
  plc::TIME now{};
  const plc::TIME dt = std::chrono::milliseconds(1);
  std::uint16_t crc1 = 0;
  std::uint32_t cn = 0;
  bool toggle = false;
  std::uint64_t errors = 0;
  auto parametrize = [&](std::uint16_t source) {
    ps::FParameters p;
    p.source_add = source;
    p.dest_add = 1;
    p.wd_time_ms = 10000;
    p.ipar_crc = 0x1234ABCD;
    std::array<std::uint8_t, ps::kFParamBlockSize> b{};
    ps::encode(p, b);
    ASSERT_EQ(m.write_record(ps::kFParamRecordIndex, b), plc::io::RecordError::None);
    crc1 = p.par_crc;
    cn = 0;
    toggle = false;
  };
  parametrize(10);
  const std::array<std::uint8_t, 4> pool[] = {
      {0x01, 0x00, 0x00, 0x03}, {0x00, 0x00, 0x00, 0x00}, {0x81, 0x02, 0x00, 0x01}};
  std::array<std::uint8_t, 8> req{};
  int checked = 0, wrong = 0, foreign = 0;
  for (int i = 0; i < 300000; ++i) {
    now += dt;
    const int event = rnd.below(20000);
    if (event == 0) {
      parametrize(static_cast<std::uint16_t>(10 + rnd.below(5)));
    } else if (event == 1) {
      m.power_cycle();  // the CRC error count goes on
      parametrize(static_cast<std::uint16_t>(10 + rnd.below(5)));
    }
    bool fresh = false, bad = false, seeded_foreign = false;
    if (rnd.below(8) != 0) {  // a new request (else the last bytes again)
      fresh = true;
      toggle = !toggle;
      std::array<std::uint8_t, 4> data = pool[rnd.below(3)];
      if (rnd.below(50) == 0)
        for (auto& b : data) b = static_cast<std::uint8_t>(rnd.below(256));
      std::uint8_t control = toggle ? ps::cb::kToggleH : 0;
      if (rnd.below(2) == 0) control |= ps::cb::kOaReq;
      if (rnd.below(5000) == 0) control |= ps::cb::kRConsNr;
      if (rnd.below(300) == 0) control |= ps::cb::kActivateFv;
      cn = (control & ps::cb::kRConsNr) ? 0u : ps::next_cons_nr(cn);
      std::uint32_t crc = ps::compute_crc2(data, control, cn, crc1);
      bad = rnd.below(10) == 0;
      if (bad) crc ^= 1u + static_cast<std::uint32_t>(rnd.below(0xFFFFFF));
      std::copy(data.begin(), data.end(), req.begin());
      req[4] = control;
      req[5] = static_cast<std::uint8_t>(crc >> 16);
      req[6] = static_cast<std::uint8_t>(crc >> 8);
      req[7] = static_cast<std::uint8_t>(crc);
      errors += bad;
      if (rnd.below(500) == 0) {
        m.answer_as_foreign_device(1);
        seeded_foreign = true;
      }
    }
    std::array<std::uint8_t, 8> resp{};
    m.step(now, dt, req, resp);
    ASSERT_EQ(m.crc_errors(), errors) << "step " << i;
    if (!fresh) continue;
    ASSERT_EQ(m.cons_nr(), cn) << "step " << i;
    const std::uint16_t seed = seeded_foreign ? static_cast<std::uint16_t>(crc1 ^ 0x5A5Au) : crc1;
    ASSERT_TRUE(ps::check_pdu(resp, 4, cn, seed)) << "step " << i;
    ++checked;
    wrong += bad;
    foreign += seeded_foreign;
  }
  EXPECT_GT(checked, 200000);
  EXPECT_GT(wrong, 20000);
  EXPECT_GT(foreign, 100);
}

// step() integrates the encoder position only when the sum can change it
// (integrate_): a zero rate adds +-0.0, which leaves every position but
// -0.0 (-0.0 + +0.0 is +0.0) and NaN as it is. The position after each step
// must be, bit for bit, the full sum (spec nord-profisafe.md §8.3 drive
// model: the position integrates the speed, P811 ratio, P812 pulses); fails
// when a zero rate also skips the sum on -0.0.
TEST(SafetyModelCaches, PositionSkipsOnlySumsThatChangeNothing_Spec8_3) {
  Rig r({{"p811", "1.0"}, {"p812", "5"}});
  plc::sim::NordIParams ip;
  ip.p811 = 1.0;
  ip.p812 = 5;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double speeds[] = {0.0, -0.0, 12.5, 0.0, -7.0, -0.0};
  const double positions[] = {0.0, -0.0, nan, 3.25, -1e9, inf, -inf, 0.0};
  const double dt_s = std::chrono::duration<double>(r.dt).count();
  for (double s : speeds) {
    for (double p : positions) {
      r.model->set_speed_rpm(s);
      r.model->set_position_inc(p);
      double expect = p;
      for (int k = 0; k < 4; ++k) {
        r.device_only(1);
        expect += s / 60.0 / ip.p811 * ip.pulses() * dt_s;
        EXPECT_EQ(std::bit_cast<std::uint64_t>(r.model->position_inc()),
                  std::bit_cast<std::uint64_t>(expect))
            << "speed " << s << " position " << p << " step " << k;
      }
    }
    // The position goes on from where the sums left it, the speed changes.
    r.model->set_speed_rpm(s);
  }
}

}  // namespace

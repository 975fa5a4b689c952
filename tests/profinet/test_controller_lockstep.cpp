// The controller against PnDevice hosting the real device models, in
// lockstep virtual time over the in-memory links (pn_loop.hpp): the
// bring-up sequence of fieldbus-masters.md §1, record read/write through
// the DeviceLink queue, alarms, device loss within the data-hold time and
// the automatic reconnect, bad frames counted and dropped, Release.
#include <gtest/gtest.h>

#include <algorithm>

#include "hiwin_e1/hiwin_e1_model.hpp"
#include "plc/io/byte_order.hpp"
#include "plc/profinet/wire/cyclic.hpp"
#include "plc/profinet/wire/dcp.hpp"
#include "plc/profinet/wire/ethernet.hpp"
#include "pn_loop.hpp"

namespace {

using namespace pntest;
namespace io = plc::io;

io::ModelParams telegram(int t) {
  io::ModelParams p;
  p.set("telegram", std::to_string(t));
  return p;
}

std::unique_ptr<plc::sim::HiwinE1Model> e1_model() {
  return std::make_unique<plc::sim::HiwinE1Model>(plc::sim::HiwinE1Config{});
}

struct Lockstep : ::testing::Test {
  Lockstep() : loop(config()) { loop.add("hiwin_e1", telegram(111), e1_model()); }
  static ControllerConfig config() {
    ControllerConfig c;
    c.retry = std::chrono::milliseconds(100);
    return c;
  }
  void bring_up() {
    ASSERT_TRUE(loop.run_until(
        [&] {
          return loop.online(0) && loop.devices[0].dev->state() == PnDeviceState::DataExchange;
        },
        500));
  }
  PnLoop loop;
};

// §1 items 1-6: DCP identify, Connect, PrmEnd, ApplicationReady answered
// with DONE, data exchange on both sides.
TEST_F(Lockstep, FieldbusMasters1_BringUpReachesDataExchangeOnBothSides) {
  // The states seen at the end of each step: a forward walk through
  // Identifying, Connecting, (Writing,) PrmEnd, AwaitReady to Online (one
  // step may pass several), never back.
  const std::vector<ArState> order{ArState::Waiting, ArState::Identifying, ArState::Connecting,
                                   ArState::Writing, ArState::PrmEnd,      ArState::AwaitReady,
                                   ArState::Online};
  std::size_t at = 0;
  bool forward = true;
  ASSERT_TRUE(loop.run_until(
      [&] {
        const ArState s = loop.ctrl->state(0);
        const auto k =
            static_cast<std::size_t>(std::find(order.begin(), order.end(), s) - order.begin());
        forward = forward && k < order.size() && k >= at;
        at = std::max(at, k);
        return s == ArState::Online;
      },
      500));
  EXPECT_TRUE(forward) << "the bring-up went back a step";
  loop.run_until([] { return false; }, 20);
  const PnDevice& dev = *loop.devices[0].dev;
  EXPECT_EQ(dev.state(), PnDeviceState::DataExchange);
  EXPECT_EQ(dev.counters().connects, 1u);
  EXPECT_GE(dev.counters().app_ready_sent, 1u);
  const DeviceCounters& c = loop.ctrl->counters(0);
  EXPECT_EQ(c.connects, 1u);
  EXPECT_GE(c.frames_in, 10u);
  EXPECT_GE(c.frames_out, 10u);
  EXPECT_EQ(c.bad_total(), 0u);
  EXPECT_EQ(c.lost, 0u);
  EXPECT_EQ(c.late, 0u);
  EXPECT_EQ(loop.ctrl->link(0).state(), io::DeviceState::Online);
}

// §1 item 6: output frames start right after the Connect response, with
// IOPS and IOCS good from the first frame (the device enters data exchange
// only after it has valid controller frames).
TEST_F(Lockstep, FieldbusMasters1_6_OutputFramesStartAtTheConnectResponseWithGoodIoxs) {
  auto tap = loop.hub.port(Mac{0x02, 0, 0, 0, 0xEE, 0xEE});
  std::array<std::uint8_t, 1600> buf{};
  bool first_checked = false;
  for (int i = 0; i < 500 && !loop.online(0); ++i) {
    const bool before = loop.ctrl->state(0) == ArState::Connecting;
    loop.step();
    if (before && loop.ctrl->state(0) != ArState::Connecting &&
        loop.ctrl->state(0) != ArState::Waiting) {
      EXPECT_GE(loop.ctrl->counters(0).frames_out, 1u)
          << "no output frame with the Connect response";
    }
    for (std::size_t n; (n = tap->receive(buf, std::chrono::nanoseconds(0))) > 0;) {
      PnFrameView v;
      if (first_checked || !decode_pn_frame(std::span(buf).first(n), v) ||
          v.src != loop.ctrl_eth->mac() || !is_rt_class1(v.frame_id))
        continue;
      CyclicView c;
      ASSERT_TRUE(decode_cyclic(std::span(buf).first(n), 0, c));
      EXPECT_EQ(c.header.data_status, 0x35);
      EXPECT_EQ(c.header.transfer_status, 0);
      EXPECT_TRUE(v.vlan_tci.has_value()) << "IOCRTagHeader priority 6";
      // Telegram 111 out: 24 data bytes, IOPS, then the IOCS of the input
      // CR's submodules (DAP, interface, port, telegram): all 0x80.
      ASSERT_GE(c.c_sdu.size(), 29u);
      for (std::size_t k = 24; k < 29; ++k) EXPECT_EQ(c.c_sdu[k], 0x80) << "byte " << k;
      first_checked = true;
    }
  }
  EXPECT_TRUE(first_checked);
  EXPECT_TRUE(loop.online(0));
}

// hiwin-e1-profinet.md §6.4 Tables 4.3.1.1/4.3.1.2: a PROFIdrive read of
// PNU 922 (telegram selection) through WRREC + RDREC on the DeviceLink,
// carried by RPC Write/Read.
TEST_F(Lockstep, E1_6_4_ParameterReadThroughTheRecordPath) {
  bring_up();
  io::RecordRequest wr, rd;
  const std::uint8_t req[] = {0x01, 0x01, 0x00, 0x01, 0x10, 0x00, 0x03, 0x9A, 0x00, 0x00};
  ASSERT_TRUE(wr.prepare_write(0xB02E, req));
  ASSERT_TRUE(loop.ctrl->link(0).submit(wr));
  ASSERT_TRUE(loop.run_until([&] { return !wr.busy(); }, 100));
  ASSERT_EQ(wr.status(), io::RecordStatus::Done) << wr.error_code();
  rd.prepare_read(0xB02E);
  ASSERT_TRUE(loop.ctrl->link(0).submit(rd));
  ASSERT_TRUE(loop.run_until([&] { return !rd.busy(); }, 100));
  ASSERT_EQ(rd.status(), io::RecordStatus::Done) << rd.error_code();
  const auto d = rd.data();
  ASSERT_GE(d.size(), 8u);
  EXPECT_EQ(d[0], 0x01);  // reference mirrored
  EXPECT_EQ(d[1], 0x01);  // response ID: read OK
  EXPECT_EQ(d[4], 0x06);  // Uint16
  EXPECT_EQ(io::load_be<std::uint16_t>(d, 6), 111);
  EXPECT_EQ(loop.ctrl->counters(0).records_ok, 2u);
}

TEST_F(Lockstep, RecordOfAnUnknownIndexFailsWithTheDevicesError) {
  bring_up();
  io::RecordRequest rd;
  rd.prepare_read(0x7777);
  ASSERT_TRUE(loop.ctrl->link(0).submit(rd));
  ASSERT_TRUE(loop.run_until([&] { return !rd.busy(); }, 100));
  EXPECT_EQ(rd.status(), io::RecordStatus::Error);
  EXPECT_EQ(rd.error(), io::RecordError::InvalidIndex);
  EXPECT_EQ(loop.ctrl->counters(0).records_error, 1u);
  EXPECT_TRUE(loop.online(0)) << "a refused record does not touch the AR";
}

// §1 item 7: an alarm is acknowledged (ACK-RTA, then AlarmAck) and shows up
// on the DeviceLink and in diagnostics.
TEST_F(Lockstep, FieldbusMasters1_7_AlarmIsAcknowledgedAndVisible) {
  bring_up();
  const std::uint8_t data[] = {0x00, 0x01, 0x00, 0x05};
  ASSERT_TRUE(loop.devices[0].dev->raise_alarm(AlarmKind::Diagnosis, 0x8000, data));
  ASSERT_TRUE(loop.run_until([&] { return loop.ctrl->link(0).last_alarm().count == 1; }, 50));
  const io::DeviceAlarm a = loop.ctrl->link(0).last_alarm();
  EXPECT_EQ(a.type, 1);  // diagnosis
  EXPECT_EQ(a.usi, 0x8000);
  EXPECT_EQ(a.slot, 1);
  EXPECT_EQ(a.data, 0x00010005u);
  ASSERT_TRUE(
      loop.run_until([&] { return loop.devices[0].dev->counters().alarms_acked == 1; }, 50));
  EXPECT_EQ(loop.ctrl->counters(0).alarms, 1u);
  EXPECT_NE(loop.ctrl->diagnostics(0).find("last alarm: type 1"), std::string::npos)
      << loop.ctrl->diagnostics(0);
  // A second one (the sequence numbers go on).
  ASSERT_TRUE(loop.devices[0].dev->raise_alarm(AlarmKind::Process, 0x0001, data));
  ASSERT_TRUE(loop.run_until([&] { return loop.ctrl->link(0).last_alarm().count == 2; }, 50));
  EXPECT_EQ(loop.ctrl->link(0).last_alarm().type, 2);
  ASSERT_TRUE(
      loop.run_until([&] { return loop.devices[0].dev->counters().alarms_acked == 2; }, 50));
  EXPECT_TRUE(loop.online(0));
}

// A device that stops answering is lost within the data-hold time (3 x 1 ms
// here), its inputs read zero and its link is Offline; when it answers
// again the controller reconnects by itself.
TEST_F(Lockstep, DeviceLossWithinDataHoldTimeThenAutomaticReconnect) {
  bring_up();
  loop.run_until([] { return false; }, 20);
  bool nonzero = false;
  for (auto b : loop.ctrl->inputs(0)) nonzero |= b != 0;
  EXPECT_TRUE(nonzero) << "the E1's status words";
  loop.devices[0].powered = false;
  int steps = 0;
  ASSERT_TRUE(loop.run_until(
      [&] {
        ++steps;
        return !loop.online(0);
      },
      100));
  // The last frame was taken at the step before; the watchdog fires once
  // more than 3 ms have passed without one.
  EXPECT_GE(steps, 3);
  EXPECT_LE(steps, 4);
  EXPECT_EQ(loop.ctrl->link(0).state(), io::DeviceState::Offline);
  for (auto b : loop.ctrl->inputs(0)) ASSERT_EQ(b, 0);
  EXPECT_EQ(loop.ctrl->counters(0).losses, 1u);
  EXPECT_NE(loop.ctrl->diagnostics(0).find("no valid input frame"), std::string::npos);
  // No reconnect while it stays silent; then it comes back.
  loop.run_until([] { return false; }, 300);
  EXPECT_FALSE(loop.online(0));
  loop.devices[0].powered = true;
  ASSERT_TRUE(loop.run_until([&] { return loop.online(0); }, 1000));
  EXPECT_EQ(loop.ctrl->counters(0).connects, 2u);
}

// Bad frames are counted under their reason and dropped; inputs stay as
// the last valid frame left them.
TEST_F(Lockstep, BadFramesAreCountedByReasonAndDropped) {
  bring_up();
  loop.run_until([] { return false; }, 10);
  auto rogue = loop.hub.port(Mac{0x02, 0, 0, 0, 0xBA, 0xD0});
  // Capture one genuine device frame to replay and mutate.
  auto tap = loop.hub.port(Mac{0x02, 0, 0, 0, 0xEE, 0xEE});
  loop.step();
  std::array<std::uint8_t, 1600> buf{};
  std::vector<std::uint8_t> good;
  for (std::size_t n; (n = tap->receive(buf, std::chrono::nanoseconds(0))) > 0;) {
    PnFrameView v;
    if (decode_pn_frame(std::span(buf).first(n), v) && is_rt_class1(v.frame_id) &&
        v.src == loop.devices[0].eth->mac())
      good.assign(buf.begin(), buf.begin() + static_cast<long>(n));
  }
  ASSERT_FALSE(good.empty());
  const std::vector<std::uint8_t> inputs_before(loop.ctrl->inputs(0).begin(),
                                                loop.ctrl->inputs(0).end());
  auto send = [&](std::vector<std::uint8_t> f) { rogue->send(f); };
  // Another source MAC.
  auto f = good;
  f[6 + 5] ^= 0x55;
  send(f);
  // Truncated.
  send(std::vector<std::uint8_t>(good.begin(), good.begin() + 30));
  // A stale cycle counter (the genuine frame again).
  send(good);
  // TransferStatus not 0, DataValid off: on a fresh counter.
  const std::size_t apdu = good.size() - 4;
  f = good;
  f[apdu] = static_cast<std::uint8_t>(f[apdu] + 0x40);
  f[apdu + 3] = 1;
  send(f);
  f = good;
  f[apdu] = static_cast<std::uint8_t>(f[apdu] + 0x40);
  f[apdu + 2] &= static_cast<std::uint8_t>(~0x04);
  send(f);
  loop.ctrl->poll(loop.now);
  const DeviceCounters& c = loop.ctrl->counters(0);
  EXPECT_EQ(c.bad[static_cast<int>(BadFrame::SourceMac)], 1u);
  EXPECT_EQ(c.bad[static_cast<int>(BadFrame::Length)], 1u);
  EXPECT_EQ(c.bad[static_cast<int>(BadFrame::StaleCounter)], 1u);
  EXPECT_EQ(c.bad[static_cast<int>(BadFrame::TransferStatus)], 1u);
  EXPECT_EQ(c.bad[static_cast<int>(BadFrame::DataInvalid)], 1u);
  EXPECT_EQ(std::vector<std::uint8_t>(loop.ctrl->inputs(0).begin(), loop.ctrl->inputs(0).end()),
            inputs_before);
  // An unknown FrameID addressed to us: not any AR's.
  f = good;
  const std::size_t fid = f[12] == 0x81 ? 18 : 14;
  f[fid] = 0xF7;
  f[fid + 1] = 0x00;
  const auto before = loop.ctrl->unmatched_frames();
  send(f);
  loop.ctrl->poll(loop.now);
  EXPECT_EQ(loop.ctrl->unmatched_frames(), before + 1);
  EXPECT_TRUE(loop.online(0));
  EXPECT_NE(loop.ctrl->diagnostics(0).find("source-mac 1"), std::string::npos)
      << loop.ctrl->diagnostics(0);
}

// Release on stop: the device's AR ends as Released, not by its watchdog.
TEST_F(Lockstep, ReleaseAllEndsTheArsCleanly) {
  bring_up();
  bool released = false;
  loop.devices[0].dev->set_event_sink(
      [&](const PnDeviceEvent& e) { released |= e.kind == PnDeviceEvent::Kind::Released; });
  loop.ctrl->release_all(loop.now);
  ASSERT_TRUE(loop.run_until([&] { return !loop.ctrl->releasing(); }, 100));
  EXPECT_TRUE(released);
  EXPECT_EQ(loop.devices[0].dev->state(), PnDeviceState::Idle);
  EXPECT_EQ(loop.ctrl->link(0).state(), io::DeviceState::Offline);
  loop.run_until([] { return false; }, 2000);
  EXPECT_EQ(loop.ctrl->state(0), ArState::Waiting) << "stopped: no reconnect";
}

// Two runs of the same scenario give identical counters (deterministic).
TEST(LockstepDeterminism, TwoRunsAreIdentical) {
  std::string diag[2];
  for (int i = 0; i < 2; ++i) {
    PnLoop loop;
    loop.add("hiwin_e1", telegram(111), e1_model());
    loop.run_until([] { return false; }, 1500);
    diag[i] = loop.ctrl->diagnostics(0);
  }
  EXPECT_EQ(diag[0], diag[1]);
}

}  // namespace

// The CAN transport: the UDP datagram (cannelloni format v2), the pcap
// writer (LINKTYPE_CAN_SOCKETCAN), SocketCAN error-frame handling, and the
// UDP hub's "every node sees every frame, its own too".
#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <poll.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "plc/can/bus.hpp"
#include "plc/can/fan_out.hpp"
#include "plc/can/mem_bus.hpp"
#include "plc/can/pcap_writer.hpp"
#include "plc/can/socketcan_bus.hpp"
#include "plc/can/udp_bus.hpp"
#include "plc/can/udp_datagram.hpp"

using namespace plc::can;

namespace {
Frame frame(std::uint32_t id, std::initializer_list<std::uint8_t> d) {
  Frame f;
  f.id = id;
  f.len = static_cast<std::uint8_t>(d.size());
  std::copy(d.begin(), d.end(), f.data.begin());
  return f;
}
}  // namespace

// cannelloni's UDP format v2 (fieldbus-masters.md §2): version 2, op code 0,
// sequence, 16-bit count, then can_id (4 bytes BE), length, data.
TEST(UdpDatagram, KnownAnswerCannelloniV2) {
  const Frame f[] = {frame(0x5EC, {0x80, 0x4B, 0x03, 0x01, 0x03, 0x00}),
                     frame(0x3C5 | Frame::kRtr, {})};
  std::array<std::uint8_t, 64> out{};
  const std::size_t n = udp::encode(7, f, out);
  const std::vector<std::uint8_t> expect = {2,    0,    7,    0,    2,  // header
                                            0x00, 0x00, 0x05, 0xEC, 6,  // frame 1
                                            0x80, 0x4B, 0x03, 0x01, 0x03, 0x00,
                                            0x40, 0x00, 0x03, 0xC5, 0};  // frame 2 (RTR)
  ASSERT_EQ(n, expect.size());
  EXPECT_TRUE(std::equal(expect.begin(), expect.end(), out.begin()));
  std::array<Frame, 4> back{};
  ASSERT_EQ(udp::decode({out.data(), n}, back), 2);
  EXPECT_EQ(back[0].id, 0x5ECu);
  EXPECT_EQ(back[0].len, 6);
  EXPECT_EQ(back[0].data[1], 0x4B);
  EXPECT_TRUE(back[1].remote());
}

TEST(UdpDatagram, MalformedDatagramsAreRejectedWhole) {
  std::array<Frame, 4> out{};
  const std::vector<std::vector<std::uint8_t>> bad = {
      {},                                                         // empty
      {1, 0, 0, 0, 0},                                            // version 1
      {2, 1, 0, 0, 0},                                            // op code ACK
      {2, 0, 0, 0, 1, 0, 0, 1, 0, 9, 1, 2, 3, 4, 5, 6, 7, 8, 9},  // length 9 (CAN FD or junk)
      {2, 0, 0, 0, 1, 0, 0, 1, 0, 2, 1},                          // count says 1 frame, data short
      {2, 0, 0, 0, 1, 0, 0, 1, 0, 1, 1, 0xFF},                    // trailing byte
      {2, 0, 0, 0, 1, 0, 0, 0x08, 0, 0},                          // 11-bit frame with id 0x800
      {2, 0, 0, 0, 5},  // 5 frames announced, more than out holds
  };
  for (const auto& d : bad) EXPECT_EQ(udp::decode(d, out), -1) << d.size();
  const std::vector<std::uint8_t> keep_alive = {2, 0, 9, 0, 0};
  EXPECT_EQ(udp::decode(keep_alive, out), 0);
}

// pcap global header + one record of link type 227 (LINKTYPE_CAN_SOCKETCAN):
// the can_id is big-endian in this link type.
TEST(PcapWriter, LinkType227RecordLayout) {
  const auto path = std::filesystem::temp_directory_path() / "plc_test_can.pcap";
  {
    PcapWriter w(path.string());
    w.write(frame(0x40D, {0x01, 0x02}), 1'500'000'000);
  }
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> b((std::istreambuf_iterator<char>(in)), {});
  std::filesystem::remove(path);
  ASSERT_EQ(b.size(), 24u + 16u + 16u);
  EXPECT_EQ(b[0], 0xD4);  // magic a1b2c3d4, little-endian file
  EXPECT_EQ(b[3], 0xA1);
  EXPECT_EQ(b[20], 227);
  EXPECT_EQ(b[24], 1);                                      // ts_sec = 1
  EXPECT_EQ(b[28] | (b[29] << 8) | (b[30] << 16), 500000);  // ts_usec
  EXPECT_EQ(b[32], 16);                                     // incl_len
  const std::uint8_t* c = &b[40];
  EXPECT_EQ(c[0], 0x00);
  EXPECT_EQ(c[2], 0x04);
  EXPECT_EQ(c[3], 0x0D);
  EXPECT_EQ(c[4], 2);
  EXPECT_EQ(c[8], 0x01);
  EXPECT_EQ(c[9], 0x02);
}

// linux/can/error.h: bus-off and controller-passive error frames, and the
// restart that ends bus-off.
TEST(SocketCan, ErrorFramesDriveTheBusState) {
  Frame busoff;
  busoff.id = Frame::kErr | CAN_ERR_BUSOFF;
  busoff.len = 8;
  EXPECT_EQ(bus_state_after(BusState::ErrorActive, busoff), BusState::BusOff);
  Frame passive;
  passive.id = Frame::kErr | CAN_ERR_CRTL;
  passive.len = 8;
  passive.data[1] = CAN_ERR_CRTL_TX_PASSIVE;
  EXPECT_EQ(bus_state_after(BusState::ErrorActive, passive), BusState::ErrorPassive);
  Frame restarted;
  restarted.id = Frame::kErr | CAN_ERR_RESTARTED;
  restarted.len = 8;
  EXPECT_EQ(bus_state_after(BusState::BusOff, restarted), BusState::ErrorActive);
  EXPECT_EQ(bus_state_after(BusState::BusOff, frame(0x123, {1})), BusState::BusOff);
}

TEST(SocketCan, MissingInterfaceIsAClearError) {
  try {
    SocketCanBus b("nosuchcan9");
    FAIL() << "opened a missing interface";
  } catch (const BusError& e) {
    EXPECT_NE(std::string(e.what()).find("nosuchcan9"), std::string::npos);
  }
  EXPECT_THROW(open_bus("tcp:1.2.3.4:5"), BusError);
  EXPECT_THROW(open_bus("udp:127.0.0.1"), BusError);
}

TEST(MemBus, EveryNodeSeesEveryFrameItsOwnToo) {
  auto wire = MemWire::create();
  auto a = wire->attach(), b = wire->attach();
  ASSERT_TRUE(a->send(frame(0x100, {1})));
  Frame f;
  ASSERT_TRUE(a->receive(f));
  EXPECT_EQ(f.id, 0x100u);
  ASSERT_TRUE(b->receive(f));
  EXPECT_FALSE(b->receive(f));
}

// Waits (bounded: count and poll timeout) until `bus` delivers a frame.
bool receive_within(Bus& bus, Frame& f, int max_waits = 200) {
  for (int i = 0; i < max_waits; ++i) {
    if (bus.receive(f)) return true;
    pollfd p{bus.fd(), POLLIN, 0};
    poll(&p, 1, 10);
  }
  return false;
}

TEST(UdpBus, HubForwardsEveryFrameToEveryNodeIncludingTheSender) {
  UdpHub hub("127.0.0.1", 0);
  UdpBus a("127.0.0.1", hub.port()), b("127.0.0.1", hub.port());
  // The hub learns a node from its keep-alive; until both are known a frame
  // may miss one, so send until both have seen one (bounded).
  Frame f;
  bool a_seen = false, b_seen = false;
  for (int i = 0; i < 100 && !(a_seen && b_seen); ++i) {
    a.send(frame(0x3C5, {static_cast<std::uint8_t>(i)}));
    if (receive_within(a, f, 5)) a_seen = a_seen || f.id == 0x3C5;
    if (receive_within(b, f, 5)) b_seen = b_seen || f.id == 0x3C5;
  }
  EXPECT_TRUE(a_seen) << "no echo of our own frame";
  EXPECT_TRUE(b_seen);
  EXPECT_GT(hub.forwarded(), 0u);
  EXPECT_EQ(a.counters().rx_bad, 0u);
}

TEST(FanOut, NodesInOneProcessEachSeeEveryFrame) {
  auto wire = MemWire::create();
  auto conn = wire->attach();
  FanOut fan(*conn);
  auto n1 = fan.node(), n2 = fan.node();
  n1->send(frame(0x7, {}));
  int tapped = 0;
  fan.pump([&](const Frame&) { ++tapped; });
  Frame f;
  EXPECT_TRUE(n1->receive(f));
  EXPECT_TRUE(n2->receive(f));
  EXPECT_EQ(tapped, 1);
}

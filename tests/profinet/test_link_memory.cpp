// The in-memory transports (lockstep tests in virtual time): a frame sent is
// receivable at once by every other port, only EtherType 0x8892 (tagged or
// not) is delivered (the contract of EthernetPort, as on AF_PACKET), and the
// fault hooks drop / delay / cut what a port sends.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "plc/profinet/link/open_link.hpp"

namespace pn = plc::profinet;
using namespace std::chrono_literals;

namespace {

std::vector<std::uint8_t> frame(const pn::Mac& dst, const pn::Mac& src, std::uint8_t tag_byte,
                                bool vlan = false, std::uint16_t type = 0x8892) {
  std::vector<std::uint8_t> f(dst.begin(), dst.end());
  f.insert(f.end(), src.begin(), src.end());
  if (vlan) f.insert(f.end(), {0x81, 0x00, 0xC0, 0x00});  // priority 6, VLAN 0
  f.push_back(static_cast<std::uint8_t>(type >> 8));
  f.push_back(static_cast<std::uint8_t>(type));
  f.insert(f.end(), {0xFE, 0xFE, tag_byte});
  f.resize(std::max<std::size_t>(f.size(), 60), 0);
  return f;
}

std::vector<std::uint8_t> take(pn::EthernetPort& p) {
  std::vector<std::uint8_t> buf(pn::kMaxFrameLength);
  buf.resize(p.receive(buf, 0ns));
  return buf;
}

}  // namespace

TEST(LinkMemoryEthernet, FrameIsAtOnceAtEveryOtherPortNotTheSender) {
  pn::MemoryEthernet hub;
  auto a = hub.port(), b = hub.port(), c = hub.port();
  EXPECT_NE(a->mac(), b->mac());
  EXPECT_EQ(a->mac()[0] & 0x03, 0x02);  // locally administered unicast
  const auto f = frame(pn::kDcpIdentifyMulticast, a->mac(), 1);
  ASSERT_TRUE(a->send(f));
  EXPECT_EQ(take(*b), f);
  EXPECT_EQ(take(*c), f);
  EXPECT_TRUE(take(*a).empty());
  EXPECT_TRUE(take(*b).empty());
  EXPECT_EQ(a->counters().sent.load(), 1u);
  EXPECT_EQ(b->counters().received.load(), 1u);
}

// The queues are rings of pooled buffers that grow while frames are in
// flight: the order holds across a ring that wraps and then grows, frames
// shared by two receivers stay intact until both took them, and the
// per-port limit (kMemoryQueueLimit) still drops and counts the excess.
TEST(LinkMemoryEthernet, QueuesKeepTheOrderAcrossGrowthAndDropPastTheLimit) {
  pn::MemoryEthernet hub;
  auto a = hub.port(), b = hub.port(), c = hub.port();
  std::uint8_t next_sent = 0, next_b = 0;
  auto send = [&](int n) {
    for (int i = 0; i < n; ++i) ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), next_sent++)));
  };
  auto take_b = [&](int n) {
    for (int i = 0; i < n; ++i) {
      const auto f = take(*b);
      ASSERT_EQ(f.size(), 60u);
      EXPECT_EQ(f[16], next_b++);
    }
  };
  send(20);
  take_b(10);
  send(40);  // b's ring: wrapped, then grown with 10 still queued
  take_b(50);
  EXPECT_TRUE(take(*b).empty());
  for (std::uint8_t k = 0; k < 60; ++k) EXPECT_EQ(take(*c)[16], k) << "c's copy of frame " << +k;
  EXPECT_TRUE(take(*c).empty());
  const std::size_t limit = pn::kMemoryQueueLimit;
  for (std::size_t i = 0; i < limit + 3; ++i)
    ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), static_cast<std::uint8_t>(i))));
  EXPECT_EQ(b->counters().rx_dropped.load(), 3u);
  std::size_t taken = 0;
  for (std::size_t i = 0; i < limit + 3 && !take(*b).empty(); ++i) ++taken;
  EXPECT_EQ(taken, limit);
}

// fieldbus-masters.md §1 item 6: 0x8892 with and without a VLAN tag.
TEST(LinkMemoryEthernet, DeliversProfinetTaggedAndUntaggedOnly) {
  pn::MemoryEthernet hub;
  auto a = hub.port(), b = hub.port();
  const auto tagged = frame(b->mac(), a->mac(), 2, true);
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 9, false, 0x0800)));  // IPv4: not ours
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 8, true, 0x88CC)));   // tagged LLDP: not ours
  ASSERT_TRUE(a->send(tagged));
  EXPECT_EQ(take(*b), tagged);
  EXPECT_TRUE(take(*b).empty());
}

TEST(LinkMemoryEthernet, FrameLongerThanTheBufferIsDroppedAndCounted) {
  pn::MemoryEthernet hub;
  auto a = hub.port(), b = hub.port();
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 1)));
  std::vector<std::uint8_t> small(20);
  EXPECT_EQ(b->receive(small, 0ns), 0u);
  EXPECT_EQ(b->counters().rx_dropped.load(), 1u);
}

TEST(LinkMemoryEthernet, DropNextAndDelayNextInHubTime) {
  pn::MemoryEthernet hub;
  auto a = hub.port(), b = hub.port();
  hub.drop_next(a->mac(), 2);
  for (std::uint8_t i = 1; i <= 3; ++i) ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), i)));
  auto got = take(*b);
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got[16], 3);  // the first two were lost
  EXPECT_TRUE(take(*b).empty());

  hub.set_time(10ms);
  hub.delay_next(a->mac(), 1, 3ms);
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 4)));
  EXPECT_TRUE(take(*b).empty());
  hub.set_time(12ms);
  EXPECT_TRUE(take(*b).empty());
  hub.set_time(13ms);
  got = take(*b);
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got[16], 4);
}

TEST(LinkMemoryEthernet, LinkDownSendsNothingAndReceivesNothing) {
  pn::MemoryEthernet hub;
  auto a = hub.port(), b = hub.port();
  hub.set_link_up(b->mac(), false);
  EXPECT_FALSE(b->send(frame(a->mac(), b->mac(), 1)));
  EXPECT_EQ(b->counters().send_failed.load(), 1u);
  EXPECT_TRUE(take(*a).empty());
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 2)));
  EXPECT_TRUE(take(*b).empty());
  hub.set_link_up(b->mac(), true);
  EXPECT_TRUE(take(*b).empty());  // what came while down is lost
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 3)));
  EXPECT_FALSE(take(*b).empty());
}

// A port that is not promiscuous (open_ethernet's default, as a raw socket
// without PACKET_MR_PROMISC): frames to its own MAC and to group addresses
// only; a promiscuous port on the same hub still sees everything.
TEST(LinkMemoryEthernet, NonPromiscuousPortTakesItsOwnAndGroupFramesOnly) {
  pn::MemoryEthernet hub;
  auto a = hub.port();
  auto b = hub.port(pn::Mac{}, /*promiscuous=*/false);
  auto c = hub.port(pn::Mac{}, /*promiscuous=*/false);
  auto tap = hub.port();
  const auto to_b = frame(b->mac(), a->mac(), 1);
  ASSERT_TRUE(a->send(to_b));
  EXPECT_EQ(take(*b), to_b);
  EXPECT_TRUE(take(*c).empty());
  EXPECT_EQ(take(*tap), to_b);
  const auto identify = frame(pn::kDcpIdentifyMulticast, a->mac(), 2);
  ASSERT_TRUE(a->send(identify));
  EXPECT_EQ(take(*b), identify);
  EXPECT_EQ(take(*c), identify);
  const auto broadcast = frame(pn::Mac{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF}, a->mac(), 3);
  ASSERT_TRUE(a->send(broadcast));
  EXPECT_EQ(take(*c), broadcast);
  EXPECT_EQ(c->counters().received.load(), 2u);
  pn::forget_memory_link("t0");
  auto d = pn::open_ethernet("mem:t0");
  auto e = pn::open_ethernet("mem:t0");
  auto f = pn::open_ethernet("mem:t0");
  ASSERT_TRUE(d->send(frame(e->mac(), d->mac(), 4)));
  EXPECT_FALSE(take(*e).empty());
  EXPECT_TRUE(take(*f).empty()) << "open_ethernet without promiscuous: only its own frames";
  pn::forget_memory_link("t0");
}

TEST(LinkMemoryEthernet, NamedHubsAndDuplicateMac) {
  pn::forget_memory_link("t1");
  auto a = pn::open_ethernet("mem:t1");
  auto b = pn::open_ethernet("mem:t1", pn::Mac{0x02, 0, 0, 0, 0, 0x77});
  EXPECT_THROW(pn::open_ethernet("mem:t1", pn::Mac{0x02, 0, 0, 0, 0, 0x77}), pn::LinkError);
  EXPECT_THROW(pn::open_ethernet("mem:"), pn::LinkError);
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 5)));
  EXPECT_FALSE(take(*b).empty());
  pn::memory_ethernet("t1").set_link_up(b->mac(), false);
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 6)));
  EXPECT_TRUE(take(*b).empty());
  pn::forget_memory_link("t1");
}

TEST(LinkMemoryUdp, DatagramToTheBoundPortWithItsSource) {
  pn::forget_memory_link("u1");
  const pn::Ipv4 ctrl = *pn::parse_ipv4("10.0.0.1"), dev = *pn::parse_ipv4("10.0.0.2");
  auto c = pn::open_udp("mem:u1", ctrl, pn::kPnioRpcPort);
  auto d = pn::open_udp("mem:u1", dev, pn::kPnioRpcPort);
  EXPECT_THROW(pn::open_udp("mem:u1", dev, pn::kPnioRpcPort), pn::LinkError);
  const std::vector<std::uint8_t> msg{1, 2, 3};
  ASSERT_TRUE(c->send_to(dev, pn::kPnioRpcPort, msg));
  std::vector<std::uint8_t> buf(pn::kMaxDatagram);
  pn::Ipv4 from;
  std::uint16_t port = 0;
  EXPECT_EQ(c->receive_from(buf, from, port, 0ns), 0u);
  ASSERT_EQ(d->receive_from(buf, from, port, 0ns), 3u);
  EXPECT_EQ(from, ctrl);
  EXPECT_EQ(port, pn::kPnioRpcPort);
  // Nobody bound there: lost, as on a network.
  EXPECT_TRUE(c->send_to(*pn::parse_ipv4("10.0.0.9"), 1, msg));
  pn::memory_udp("u1").drop_next(ctrl, 1);
  ASSERT_TRUE(c->send_to(dev, pn::kPnioRpcPort, msg));
  EXPECT_EQ(d->receive_from(buf, from, port, 0ns), 0u);
  pn::forget_memory_link("u1");
}

TEST(LinkAddress, MacAndIpv4TextForms) {
  EXPECT_EQ(pn::to_string(pn::kDcpIdentifyMulticast), "01:0e:cf:00:00:00");
  EXPECT_EQ(pn::parse_mac("01-0E-CF-00-00-00"), pn::kDcpIdentifyMulticast);
  EXPECT_FALSE(pn::parse_mac("01:0e:cf:00:00"));
  EXPECT_EQ(pn::parse_ipv4("192.168.0.1")->host_order, 0xC0A80001u);
  EXPECT_EQ(pn::to_string(pn::Ipv4{0x0A580001}), "10.88.0.1");
  EXPECT_FALSE(pn::parse_ipv4("192.168.0"));
  EXPECT_FALSE(pn::parse_ipv4("192.168.0.256"));
}

// A real-time thread may wait on a memory port (receive with a timeout):
// a frame sent from another thread wakes it. Bounded: the wait is at most
// 10 s, the frame is sent right after the receiver started.
TEST(LinkMemoryEthernet, ReceiveWithTimeoutWakesOnAFrameFromAnotherThread) {
  pn::MemoryEthernet hub;
  auto a = hub.port(), b = hub.port();
  std::size_t got = 0;
  std::thread rx([&] {
    std::vector<std::uint8_t> buf(pn::kMaxFrameLength);
    got = b->receive(buf, 10s);
  });
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 1)));
  rx.join();
  EXPECT_EQ(got, 60u);
  EXPECT_EQ(b->counters().received.load(), 1u);
}

// Declared single-threaded (a cell in virtual time), the hub takes no lock
// but keeps its contract: delivery to the others only, the fault hooks, and
// receive() with a timeout returns at once (nobody else could send).
TEST(LinkMemoryEthernet, SingleThreadedHubKeepsTheContract) {
  pn::MemoryEthernet hub;
  hub.set_single_threaded(true);
  EXPECT_TRUE(hub.single_threaded());
  auto a = hub.port(), b = hub.port(), c = hub.port(pn::Mac{}, /*promiscuous=*/false);
  const auto f = frame(b->mac(), a->mac(), 1);
  ASSERT_TRUE(a->send(f));
  EXPECT_EQ(take(*b), f);
  EXPECT_TRUE(take(*c).empty());  // not its MAC
  EXPECT_TRUE(take(*a).empty());
  hub.drop_next(a->mac(), 1);
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 2)));
  EXPECT_TRUE(take(*b).empty());
  hub.set_time(5ms);
  hub.delay_next(a->mac(), 1, 1ms);
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 3)));
  std::vector<std::uint8_t> buf(pn::kMaxFrameLength);
  EXPECT_EQ(b->receive(buf, 10s), 0u);  // not yet due; no wait
  hub.set_time(6ms);
  ASSERT_EQ(b->receive(buf, 10s), 60u);
  EXPECT_EQ(buf[16], 3);
  EXPECT_EQ(hub.frames_carried(), 3u);
  hub.set_single_threaded(false);
  EXPECT_FALSE(hub.single_threaded());
  ASSERT_TRUE(a->send(f));
  EXPECT_EQ(take(*b), f);
}

// receive_view() hands out the frame in the hub's buffer, no copy: the view
// stays intact while more frames are sent (the pool grows past its first
// buffers meanwhile) until the port's next receive; a frame longer than the
// caller's buffer is dropped and counted, as by receive().
TEST(LinkMemoryEthernet, ReceiveViewIsTheFrameInPlaceUntilTheNextReceive) {
  for (const bool single : {true, false}) {
    pn::MemoryEthernet hub;
    hub.set_single_threaded(single);
    auto a = hub.port(pn::Mac{}, false), b = hub.port(pn::Mac{}, false);
    std::vector<std::uint8_t> buf(pn::kMaxFrameLength);
    ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 0)));
    for (std::uint8_t i = 1; i < 100; ++i) {
      const auto v = b->receive_view(buf, 0ns);
      ASSERT_EQ(v.size(), 60u);
      EXPECT_TRUE(v.data() < buf.data() || v.data() >= buf.data() + buf.size());  // not copied
      const std::vector<std::uint8_t> seen(v.begin(), v.end());
      EXPECT_EQ(seen, frame(b->mac(), a->mac(), static_cast<std::uint8_t>(i - 1)));
      // More frames while the view is held: the next for b, and 39 that a
      // leaves queued (the pool grows past its first 16 buffers).
      ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), i)));
      if (i < 40) {
        ASSERT_TRUE(b->send(frame(a->mac(), b->mac(), i)));
      }
      EXPECT_EQ(std::vector<std::uint8_t>(v.begin(), v.end()), seen) << int(i);
    }
    EXPECT_EQ(b->counters().received.load(), 99u);
    std::vector<std::uint8_t> small(59);
    ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 7)));
    while (!b->receive_view(buf, 0ns).empty()) {
    }
    ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 8)));
    EXPECT_TRUE(b->receive_view(small, 0ns).empty());
    EXPECT_EQ(b->counters().rx_dropped.load(), 1u);
  }
}

// Unicast frames among ports that take only their own (the profinet
// plugin's ports) go straight to the destination's queue, without asking
// every port: the delivery is the hub's contract all the same. Random
// traffic (unicast to each port, to the sender itself, to nobody, group
// frames) on hubs single- and multi-threaded, with and without a
// promiscuous tap, against a model of the contract; read by receive() and
// receive_view() in turn.
TEST(LinkMemoryEthernet, UnicastDeliveryMatchesTheContractOnEveryPath) {
  for (int variant = 0; variant < 4; ++variant) {
    const bool single = variant & 1, tap = variant & 2;
    pn::MemoryEthernet hub;
    hub.set_single_threaded(single);
    std::vector<std::unique_ptr<pn::EthernetPort>> ports;
    for (int i = 0; i < 4; ++i) ports.push_back(hub.port(pn::Mac{}, false));
    if (tap) ports.push_back(hub.port(pn::Mac{}, true));
    std::vector<std::vector<std::vector<std::uint8_t>>> expected(ports.size());
    std::vector<std::size_t> next(ports.size(), 0);
    std::uint32_t seed = 12345;
    auto rnd = [&](std::uint32_t n) {
      seed = seed * 1103515245u + 12345u;
      return (seed >> 16) % n;
    };
    std::vector<std::uint8_t> buf(pn::kMaxFrameLength);
    for (int step = 0; step < 2000; ++step) {
      const std::size_t from = rnd(4);
      const std::uint32_t pick = rnd(7);
      pn::Mac dst = pick < 4    ? ports[pick]->mac()
                    : pick == 4 ? pn::Mac{0x02, 0x00, 0x00, 0x00, 0x77, 0x77}  // nobody
                    : pick == 5 ? pn::kDcpIdentifyMulticast
                                : ports[from]->mac();  // itself
      const auto f = frame(dst, ports[from]->mac(), static_cast<std::uint8_t>(step));
      ASSERT_TRUE(ports[from]->send(f));
      for (std::size_t p = 0; p < ports.size(); ++p) {
        if (p == from) continue;
        const bool promiscuous = tap && p == 4;
        if (promiscuous || pick == 5 || ports[p]->mac() == dst) expected[p].push_back(f);
      }
      const std::size_t reader = rnd(static_cast<std::uint32_t>(ports.size()));
      for (std::uint32_t n = rnd(3); n > 0; --n) {
        std::vector<std::uint8_t> got;
        if (step & 1) {
          const auto v = ports[reader]->receive_view(buf, 0ns);
          got.assign(v.begin(), v.end());
        } else {
          got.assign(buf.begin(),
                     buf.begin() + static_cast<std::ptrdiff_t>(ports[reader]->receive(buf, 0ns)));
        }
        if (next[reader] == expected[reader].size()) {
          EXPECT_TRUE(got.empty()) << variant << " " << step;
        } else {
          EXPECT_EQ(got, expected[reader][next[reader]++]) << variant << " " << step;
        }
      }
    }
    for (std::size_t p = 0; p < ports.size(); ++p) {
      while (next[p] < expected[p].size()) EXPECT_EQ(take(*ports[p]), expected[p][next[p]++]);
      EXPECT_TRUE(take(*ports[p]).empty());
    }
    EXPECT_EQ(hub.frames_carried(), 2000u);
  }
}

// queued_count() of an in-memory port is the number of messages a receive
// would find (the controller and PnDevice skip a port whose count is 0):
// it follows every send, receive, drop and link-down loss.
TEST(LinkMemory, QueuedCountIsWhatReceiveFinds) {
  for (const bool single : {true, false}) {
    pn::MemoryEthernet hub;
    hub.set_single_threaded(single);
    auto a = hub.port(pn::Mac{}, false), b = hub.port(pn::Mac{}, false);
    const std::atomic<std::size_t>* q = b->queued_count();
    ASSERT_NE(q, nullptr);
    std::vector<std::uint8_t> buf(pn::kMaxFrameLength);
    for (int round = 0; round < 3; ++round) {
      for (std::uint8_t i = 0; i < 5; ++i) ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), i)));
      EXPECT_EQ(q->load(), 5u);
      EXPECT_EQ(b->receive(buf, 0ns), 60u);
      EXPECT_EQ(q->load(), 4u);
      EXPECT_FALSE(b->receive_view(buf, 0ns).empty());
      EXPECT_EQ(q->load(), 3u);
      std::size_t left = 3;
      while (!b->receive_view(buf, 0ns).empty()) EXPECT_EQ(q->load(), --left);
      EXPECT_EQ(q->load(), 0u);
    }
    ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 9)));
    hub.set_link_up(b->mac(), false);
    EXPECT_TRUE(b->receive_view(buf, 0ns).empty());  // lost with the link
    EXPECT_EQ(q->load(), 0u);
    pn::MemoryUdp net;
    net.set_single_threaded(single);
    auto u = net.port(pn::Ipv4{0x0A000001}, 1000), v = net.port(pn::Ipv4{0x0A000002}, 1000);
    ASSERT_NE(v->queued_count(), nullptr);
    const std::vector<std::uint8_t> d{1, 2, 3};
    ASSERT_TRUE(u->send_to(pn::Ipv4{0x0A000002}, 1000, d));
    EXPECT_EQ(v->queued_count()->load(), 1u);
    pn::Ipv4 ip;
    std::uint16_t port = 0;
    EXPECT_EQ(v->receive_from(buf, ip, port, 0ns), 3u);
    EXPECT_EQ(v->queued_count()->load(), 0u);
    EXPECT_EQ(u->queued_count()->load(), 0u);
  }
}

// The per-port limit holds on the short path too (single-threaded hub,
// ports that take only their own): the excess is dropped and counted, the
// frames kept come out in order, and the port takes frames again after.
TEST(LinkMemoryEthernet, QueueLimitOnTheSingleThreadedUnicastPath) {
  pn::MemoryEthernet hub;
  hub.set_single_threaded(true);
  auto a = hub.port(pn::Mac{}, false), b = hub.port(pn::Mac{}, false);
  const std::size_t limit = pn::kMemoryQueueLimit;
  for (std::size_t i = 0; i < limit + 3; ++i)
    ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), static_cast<std::uint8_t>(i))));
  EXPECT_EQ(b->counters().rx_dropped.load(), 3u);
  EXPECT_EQ(b->queued_count()->load(), limit);
  std::vector<std::uint8_t> buf(pn::kMaxFrameLength);
  for (std::size_t i = 0; i < limit; ++i) {
    const auto v = b->receive_view(buf, 0ns);
    ASSERT_EQ(v.size(), 60u);
    EXPECT_EQ(v[16], static_cast<std::uint8_t>(i));
  }
  EXPECT_TRUE(b->receive_view(buf, 0ns).empty());
  ASSERT_TRUE(a->send(frame(b->mac(), a->mac(), 42)));
  EXPECT_EQ(take(*b)[16], 42);
  EXPECT_EQ(b->counters().rx_dropped.load(), 3u);
}

// The real transports between two network namespaces joined by a veth pair
// (netns.hpp; never a host interface): RawEthernetPort carries EtherType
// 0x8892 frames untagged and VLAN-tagged (fieldbus-masters.md §1 item 6:
// devices may send priority-6 tagged frames) byte for byte, DCP multicast
// (§1 item 1) included; SocketUdpPort carries the RPC datagrams (UDP 34964,
// §1 item 2); a missing interface or a missing CAP_NET_RAW is a LinkError
// that says so.
#include <linux/capability.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <vector>

#include "netns.hpp"
#include "plc/profinet/link/open_link.hpp"
#include "plc/profinet/link/socket_udp_port.hpp"

namespace pn = plc::profinet;
using namespace std::chrono_literals;

namespace {

std::vector<std::uint8_t> frame(const pn::Mac& dst, const pn::Mac& src, std::uint8_t id,
                                std::optional<std::uint16_t> tci, std::uint16_t type = 0x8892) {
  std::vector<std::uint8_t> f(dst.begin(), dst.end());
  f.insert(f.end(), src.begin(), src.end());
  if (tci) f.insert(f.end(), {0x81, 0x00, std::uint8_t(*tci >> 8), std::uint8_t(*tci)});
  f.push_back(static_cast<std::uint8_t>(type >> 8));
  f.push_back(static_cast<std::uint8_t>(type));
  f.insert(f.end(), {0xC0, 0x00, id});
  for (std::size_t i = f.size(); i < 64; ++i) f.push_back(static_cast<std::uint8_t>(i));
  return f;
}

// The next frame within 2 s (a bound for a loaded machine; it normally
// comes within microseconds), empty if none.
std::vector<std::uint8_t> next(pn::EthernetPort& p) {
  std::vector<std::uint8_t> buf(pn::kMaxFrameLength);
  buf.resize(p.receive(buf, 2s));
  return buf;
}

using Port = std::unique_ptr<pn::EthernetPort>;

}  // namespace

class LinkNetns : public plctest::NetnsTest {};

TEST_F(LinkNetns, RawPortsCarryUntaggedAndVlanTaggedProfinetFramesExactly) {
  Port pa = pair().in(a(), [&] { return pn::open_ethernet(a().iface); });
  Port pb = pair().in(b(), [&] { return pn::open_ethernet(b().iface); });
  ASSERT_NE(pa->mac(), pb->mac());
  ASSERT_GE(pa->fd(), 0);

  const auto untagged = frame(pb->mac(), pa->mac(), 1, std::nullopt);
  const auto prio6 = frame(pb->mac(), pa->mac(), 2, 0xC000);  // VLAN 0, priority 6
  const auto vlan5 = frame(pb->mac(), pa->mac(), 3, 0xA005);  // VLAN 5, priority 5
  const auto dcp = frame(pn::kDcpIdentifyMulticast, pa->mac(), 4, std::nullopt);
  const auto ipv4 = frame(pb->mac(), pa->mac(), 5, std::nullopt, 0x0800);
  for (const auto* f : {&ipv4, &untagged, &prio6, &vlan5, &dcp}) ASSERT_TRUE(pa->send(*f));

  EXPECT_EQ(next(*pb), untagged);
  EXPECT_EQ(next(*pb), prio6);  // the tag the kernel took off is back in place
  EXPECT_EQ(next(*pb), vlan5);
  EXPECT_EQ(next(*pb), dcp);
  std::vector<std::uint8_t> buf(pn::kMaxFrameLength);
  EXPECT_EQ(pb->receive(buf, 0ns), 0u);  // the IPv4 frame was never delivered
  EXPECT_EQ(pa->receive(buf, 0ns), 0u);  // nor are our own frames
  EXPECT_EQ(pa->counters().sent.load(), 5u);
  EXPECT_EQ(pb->counters().received.load(), 4u);

  // And back, tagged, from B.
  const auto back = frame(pa->mac(), pb->mac(), 6, 0xC000);
  ASSERT_TRUE(pb->send(back));
  EXPECT_EQ(next(*pa), back);
}

TEST_F(LinkNetns, RawPortDropsAFrameLongerThanTheBuffer) {
  Port pa = pair().in(a(), [&] { return pn::open_ethernet(a().iface); });
  Port pb = pair().in(b(), [&] { return pn::open_ethernet(b().iface); });
  ASSERT_TRUE(pa->send(frame(pb->mac(), pa->mac(), 1, std::nullopt)));
  ASSERT_TRUE(pa->send(frame(pb->mac(), pa->mac(), 2, std::nullopt)));
  std::vector<std::uint8_t> small(32);
  EXPECT_EQ(pb->receive(small, 2s), 0u);
  EXPECT_EQ(pb->counters().rx_dropped.load(), 2u);
}

TEST_F(LinkNetns, UdpDatagramsBothWaysOnPort34964) {
  const auto ipa = *pn::parse_ipv4(a().ip), ipb = *pn::parse_ipv4(b().ip);
  auto ua = pair().in(a(), [&] { return pn::open_udp(a().iface, ipa, pn::kPnioRpcPort); });
  auto ub = pair().in(b(), [&] { return pn::open_udp(b().iface, ipb, pn::kPnioRpcPort); });
  const std::vector<std::uint8_t> req{0x04, 0x00, 0x20, 0x00}, res{0x04, 0x02};
  ASSERT_TRUE(ua->send_to(ipb, pn::kPnioRpcPort, req));
  std::vector<std::uint8_t> buf(pn::kMaxDatagram);
  pn::Ipv4 from;
  std::uint16_t port = 0;
  ASSERT_EQ(ub->receive_from(buf, from, port, 2s), req.size());
  EXPECT_EQ(std::vector<std::uint8_t>(buf.begin(), buf.begin() + 4), req);
  EXPECT_EQ(from, ipa);
  EXPECT_EQ(port, pn::kPnioRpcPort);
  ASSERT_TRUE(ub->send_to(from, port, res));
  ASSERT_EQ(ua->receive_from(buf, from, port, 2s), res.size());
  EXPECT_EQ(from, ipb);
  EXPECT_EQ(ua->receive_from(buf, from, port, 0ns), 0u);
  // An address that is not in the namespace cannot be bound.
  EXPECT_THROW(pair().in(a(), [&] { return pn::SocketUdpPort(ipb, 40000).local_port(); }),
               pn::LinkError);
}

TEST_F(LinkNetns, MissingInterfaceIsAClearLinkError) {
  try {
    pair().in(a(), [] { return pn::open_ethernet("pnzz9"); });
    FAIL() << "no error for a missing interface";
  } catch (const pn::LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("'pnzz9'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no such interface"), std::string::npos) << e.what();
  }
  EXPECT_THROW(pn::open_ethernet(""), pn::LinkError);
}

TEST_F(LinkNetns, MissingCapNetRawIsAClearLinkError) {
  // Capabilities are per thread: this thread alone gives up CAP_NET_RAW.
  auto attempt = [&]() -> std::string {
    __user_cap_header_struct hdr{_LINUX_CAPABILITY_VERSION_3, 0};
    __user_cap_data_struct data[2]{};
    if (::syscall(SYS_capget, &hdr, data) != 0) return "capget failed";
    data[CAP_NET_RAW / 32].effective &= ~(1u << (CAP_NET_RAW % 32));
    if (::syscall(SYS_capset, &hdr, data) != 0) return "capset failed";
    try {
      pn::RawEthernetPort p(a().iface);
      return "opened without CAP_NET_RAW";
    } catch (const pn::LinkError& e) {
      return e.what();
    }
  };
  const std::string what = pair().in(a(), attempt);
  EXPECT_NE(what.find("CAP_NET_RAW"), std::string::npos) << what;
}

TEST_F(LinkNetns, ChildProcessRunsInsideTheNamespace) {
  const auto r = pair().run(b(), "ip -o -4 addr show dev pnb");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(b().ip + "/24"), std::string::npos) << r.output;
  // And A reaches B over the veth.
  const auto ping = pair().run(a(), "ping -c 1 -W 2 " + b().ip);
  if (ping.output.find("not found") == std::string::npos) {
    EXPECT_EQ(ping.exit_code, 0) << ping.output;
  }
}

TEST_F(LinkNetns, StartedChildRunsInItsNamespaceUntilStopped) {
  // The child waits for one UDP datagram in B (a bounded 30 s wait) and
  // prints what it got; the test sends it from A.
  auto child =
      pair().start(b(),
                   "timeout 30 python3 -c \"import socket; s=socket.socket(socket.AF_INET, "
                   "socket.SOCK_DGRAM); s.bind(('" +
                       b().ip + "', 34964)); print(s.recv(64).decode(), flush=True)\"");
  ASSERT_NE(child, nullptr);
  const auto ipa = *pn::parse_ipv4(a().ip), ipb = *pn::parse_ipv4(b().ip);
  auto ua = pair().in(a(), [&] { return pn::open_udp(a().iface, ipa, 0); });
  const std::string hello = "hello-from-a";
  // The child binds at some point after start: send until it has answered
  // by exiting (bounded: 300 tries, 100 ms apart as measured by the wait).
  int status = -1;
  for (int i = 0; i < 300 && status == -1; ++i) {
    ua->send_to(ipb, pn::kPnioRpcPort,
                std::span(reinterpret_cast<const std::uint8_t*>(hello.data()), hello.size()));
    status = child->wait(std::chrono::milliseconds(100));
  }
  EXPECT_EQ(status, 0) << child->output();
  EXPECT_NE(child->output().find(hello), std::string::npos) << child->output();
  // A child that runs on is ended by stop().
  auto sleeper = pair().start(a(), "sleep 60");
  ASSERT_NE(sleeper, nullptr);
  EXPECT_TRUE(sleeper->running());
  EXPECT_EQ(sleeper->stop(), 128 + SIGTERM);
}

TEST(LinkNetnsFixture, NamespacesAndVethAreGoneWhenThePairEnds) {
  std::string why;
  auto p = plctest::NetnsPair::create(why);
  if (!p) GTEST_SKIP() << "network namespaces unavailable, test skipped: " << why;
  const std::string na = p->a().ns, nb = p->b().ns;
  ASSERT_EQ(::access(("/run/netns/" + na).c_str(), F_OK), 0);
  p.reset();
  EXPECT_NE(::access(("/run/netns/" + na).c_str(), F_OK), 0);
  EXPECT_NE(::access(("/run/netns/" + nb).c_str(), F_OK), 0);
}

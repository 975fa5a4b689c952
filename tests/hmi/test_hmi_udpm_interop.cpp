// Our udpm transport against liblcm 1.3.1 itself, the independent peer
// (linked into this test only), over multicast on the loopback of a network
// namespace the test makes (loopback_netns.hpp; ttl=0, a group and port of
// its own): liblcm's messages reach us byte for byte and ours reach it,
// short and fragmented; the datagrams on the wire are the same bytes.
// Then the hostile datagrams of issue 22: the wrapping-offset fragment
// kills a liblcm receiver (SIGSEGV in its receive thread: the "before"),
// and leaves ours, and a bridge on it, serving.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <lcm/lcm-cpp.hpp>
#include <map>

#include "hmi_test_cell.hpp"
#include "loopback_netns.hpp"
#include "plc/hmi/transport.hpp"
#include "plc_test_sanitizers.hpp"
#include "softplc_hmi/command_t.hpp"
#include "softplc_hmi/stats_t.hpp"
#include "udpm_test_datagrams.hpp"
#include "udpm_test_socket.hpp"

using namespace plc::hmi;
using namespace plctest::udpm;
using plctest::LoopbackNetns;

namespace {

constexpr const char* kUrl = "udpm://239.255.76.99:7699?ttl=0";
constexpr std::uint32_t kGroup = 0xEFFF4C63;  // 239.255.76.99
constexpr std::uint16_t kPort = 7699;

constexpr bool kSanitized = plctest::kSanitized;

class UdpmNetns : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    ns_ = LoopbackNetns::create(why);
    if (!ns_) GTEST_SKIP() << "network namespaces unavailable, test skipped: " << why;
  }
  std::unique_ptr<Transport> ours() {
    std::string err;
    auto t = ns_->in([&] { return open_transport(kUrl, err); });
    EXPECT_TRUE(t) << err;
    return t;
  }
  // liblcm's udpm, its receive socket (made at the first subscription)
  // inside the namespace too.
  template <class Subscribe>
  std::unique_ptr<lcm::LCM> liblcm(Subscribe subscribe) {
    return ns_->in([&] {
      auto l = std::make_unique<lcm::LCM>(kUrl);
      if (l->good()) subscribe(*l);
      return l;
    });
  }
  std::unique_ptr<LoopbackNetns> ns_;
};

struct Got {
  std::map<std::string, Bytes> by_channel;
  static void on(const lcm::ReceiveBuffer* rb, const std::string& channel, Got* self) {
    const auto* p = static_cast<const std::uint8_t*>(rb->data);
    self->by_channel[channel] = Bytes(p, p + rb->data_size);
  }
};

}  // namespace

// liblcm publishes a short message and a 200 kB one (4 fragments); our
// transport hands over the same bytes on the same channels.
TEST_F(UdpmNetns, LiblcmPublishesWeReceiveIdenticalBytes) {
  auto rx = ours();
  ASSERT_TRUE(rx);
  Got got;
  rx->subscribe("INTEROP_.*", [&](const ReceiveBuffer& rb, const std::string& channel) {
    const auto* p = static_cast<const std::uint8_t*>(rb.data);
    got.by_channel[channel] = Bytes(p, p + rb.data_size);
  });
  auto peer = liblcm([](lcm::LCM&) {});
  ASSERT_TRUE(peer->good());
  const Bytes small = pattern(1000, 3), big = pattern(200000, 4);
  ASSERT_EQ(peer->publish("INTEROP_SHORT", small.data(), unsigned(small.size())), 0);
  ASSERT_EQ(peer->publish("INTEROP_BIG", big.data(), unsigned(big.size())), 0);
  for (int i = 0; i < 50 && got.by_channel.size() < 2; ++i) rx->handle_timeout(100);
  EXPECT_EQ(got.by_channel["INTEROP_SHORT"], small);
  EXPECT_EQ(got.by_channel["INTEROP_BIG"], big);
  const auto c = rx->counters();
  EXPECT_EQ(c.messages, 2U);
  EXPECT_EQ(c.fragment_ok, 4U);
  EXPECT_EQ(c.dropped(), 0U);
}

// We publish the same two; liblcm's subscriber gets the same bytes.
TEST_F(UdpmNetns, WePublishLiblcmReceivesIdenticalBytes) {
  Got got;
  auto peer = liblcm([&](lcm::LCM& l) { l.subscribeFunction("INTEROP_.*", &Got::on, &got); });
  ASSERT_TRUE(peer->good());
  auto tx = ours();
  ASSERT_TRUE(tx);
  const Bytes small = pattern(1000, 5), big = pattern(200000, 6);
  ASSERT_TRUE(tx->publish("INTEROP_SHORT", small.data(), small.size()));
  ASSERT_TRUE(tx->publish("INTEROP_BIG", big.data(), big.size()));
  for (int i = 0; i < 50 && got.by_channel.size() < 2; ++i) peer->handleTimeout(100);
  EXPECT_EQ(got.by_channel["INTEROP_SHORT"], small);
  EXPECT_EQ(got.by_channel["INTEROP_BIG"], big);
}

// On the wire: liblcm's datagrams (a fresh instance numbers from 0) are the
// ones our encoder writes, and our transport sends exactly those too.
TEST_F(UdpmNetns, OurDatagramsAreByteForByteLiblcms) {
  auto capture = ns_->in([] { return std::make_unique<GroupSocket>(kGroup, kPort, true); });
  const Bytes small = pattern(3000, 7), big = pattern(200000, 8);
  auto expect_wire = [&](const char* who) {
    for (const auto& [seqno, channel, payload] :
         {std::tuple{0U, "WIRE_SHORT", &small}, std::tuple{1U, "WIRE_BIG", &big}})
      for (const Bytes& want : encode(channel, *payload, seqno)) {
        const auto d = capture->next();
        ASSERT_TRUE(d) << who << ": a datagram of " << channel << " did not come";
        EXPECT_EQ(*d, want) << who << ": " << channel;
      }
  };
  {
    auto peer = liblcm([](lcm::LCM&) {});  // publishes only: no self-test message
    ASSERT_TRUE(peer->good());
    peer->publish("WIRE_SHORT", small.data(), unsigned(small.size()));
    peer->publish("WIRE_BIG", big.data(), unsigned(big.size()));
    expect_wire("liblcm");
  }
  auto tx = ours();
  ASSERT_TRUE(tx);
  tx->publish("WIRE_SHORT", small.data(), small.size());
  tx->publish("WIRE_BIG", big.data(), big.size());
  expect_wire("ours");
}

// The "before" of issue 22: a process subscribed with liblcm 1.3.1 dies
// with SIGSEGV (its receive thread's memcpy, lcm_udpm.c:324) at the
// wrapping-offset fragment, and never sees the valid message after it.
// In a child process, so this test survives it. (Under ASan or TSan the
// child dies by the sanitizer's SEGV report instead.)
TEST_F(UdpmNetns, WrappingOffsetFragmentKillsALiblcmReceiver) {
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ns_->fork_in([&] {
    lcm::LCM l(kUrl);
    if (!l.good()) return 3;
    struct Seen {
      bool valid = false;
      static void on(const lcm::ReceiveBuffer* rb, const std::string&, Seen* s) {
        s->valid |= rb->data_size == 5;
      }
    } seen;
    l.subscribeFunction("PLC_CMD", &Seen::on, &seen);  // joins, runs liblcm's self-test
    (void)!::write(ready[1], "R", 1);
    for (int i = 0; i < 100 && !seen.valid; ++i) l.handleTimeout(100);  // 10 s at most
    return seen.valid ? 42 : 43;
  });
  ASSERT_GT(child, 0);
  ::close(ready[1]);
  char r = 0;
  ASSERT_EQ(::read(ready[0], &r, 1), 1) << "the liblcm child did not start";
  ::close(ready[0]);
  auto tx = ns_->in([] { return std::make_unique<GroupSocket>(kGroup, kPort, false); });
  tx->send(wrapping_offset_fragment("PLC_CMD"));
  tx->send(lc02(100, "PLC_CMD", {1, 2, 3, 4, 5}));
  const auto status = plctest::wait_child(child, std::chrono::seconds(20));
  ASSERT_TRUE(status) << "the liblcm child neither died nor ended";
  ASSERT_FALSE(WIFEXITED(*status) && WEXITSTATUS(*status) == 42)
      << "liblcm survived the wrapping-offset fragment and received the next message: the "
         "installed liblcm has the fix (lcm-proj/lcm pull request 628); this test documents 1.3.1";
  if (!kSanitized) {
    ASSERT_TRUE(WIFSIGNALED(*status)) << "status " << *status;
    EXPECT_EQ(WTERMSIG(*status), SIGSEGV);
  } else {
    EXPECT_FALSE(WIFEXITED(*status) && WEXITSTATUS(*status) == 43) << "status " << *status;
  }
}

// The same datagram, and the other hostile ones, at our transport: each is
// counted under its reason, and a valid message published by liblcm right
// after them is received.
TEST_F(UdpmNetns, HostileDatagramsAreCountedAndOursKeepsReceiving) {
  auto rx = ours();
  ASSERT_TRUE(rx);
  Bytes valid;
  rx->subscribe("PLC_CMD", [&](const ReceiveBuffer& rb, const std::string&) {
    const auto* p = static_cast<const std::uint8_t*>(rb.data);
    valid.assign(p, p + rb.data_size);
  });
  auto tx = ns_->in([] { return std::make_unique<GroupSocket>(kGroup, kPort, false); });
  TransportCounters want;
  for (const auto& [d, reason] : hostile_set("PLC_CMD")) {
    tx->send(d);
    ++(want.*reason);
  }
  std::uint32_t x = 88172645U;  // and 200 datagrams of random bytes (xorshift)
  for (int i = 0; i < 200; ++i) {
    Bytes d(1 + i % 100);
    for (auto& b : d) {
      x ^= x << 13;
      x ^= x >> 17;
      x ^= x << 5;
      b = std::uint8_t(x);
    }
    d[0] = 'R';  // never a magic
    tx->send(d);
    ++(d.size() < 4 ? want.truncated : want.bad_magic);
  }
  auto peer = liblcm([](lcm::LCM&) {});
  ASSERT_TRUE(peer->good());
  const Bytes hello = pattern(5000, 9);
  peer->publish("PLC_CMD", hello.data(), unsigned(hello.size()));
  for (int i = 0; i < 50 && valid.empty(); ++i) rx->handle_timeout(100);
  EXPECT_EQ(valid, hello);
  const auto c = rx->counters();
  EXPECT_EQ(c.bad_fragment, want.bad_fragment);
  EXPECT_EQ(c.oversized, want.oversized);
  EXPECT_EQ(c.truncated, want.truncated);
  EXPECT_EQ(c.channel_unterminated, want.channel_unterminated);
  EXPECT_EQ(c.channel_too_long, want.channel_too_long);
  EXPECT_EQ(c.bad_magic, want.bad_magic);
  EXPECT_EQ(c.datagrams, want.dropped() + 1U);
  EXPECT_EQ(c.messages, 1U);
}

// The bridge on udpm (in-process, virtual time): the wrapping-offset
// fragment and the rest arrive on its command channel, then a valid
// command gets its reply; stats_t reports the transport's counters by name.
TEST_F(UdpmNetns, BridgeServesCommandsAfterHostileDatagramsAndReportsThem) {
  std::string section = plctest::kHmiSection;
  section.replace(section.find("memq://"), 7, kUrl);
  auto h = ns_->in([&] { return std::make_unique<plctest::HmiCell>(section); });
  ASSERT_TRUE(h->dbg->step(1).ok);
  auto tx = ns_->in([] { return std::make_unique<GroupSocket>(kGroup, kPort, false); });
  for (const auto& [d, reason] : hostile_set("PLC_CMD")) tx->send(d);
  auto client = ours();
  ASSERT_TRUE(client);
  std::vector<softplc_hmi::stats_t> stats;
  struct StatsSink {
    std::vector<softplc_hmi::stats_t>* out;
    void on(const softplc_hmi::stats_t& s) { out->push_back(s); }
  } sink{&stats};
  subscribe_checked<softplc_hmi::stats_t>(*client, "PLC_STATS", &sink);
  softplc_hmi::command_t c{};
  c.request_id = 77;
  c.client = "test";
  c.verb = "read";
  c.args = {"Tank.level"};
  c.n_args = 1;
  c.counter = 77;
  ASSERT_TRUE(client->publish("PLC_CMD", &c));
  for (int i = 0; i < 50 && h->replies.empty(); ++i) h->bridge->service(100);
  ASSERT_EQ(h->replies.size(), 1U);
  EXPECT_TRUE(h->replies[0].ok) << h->replies[0].refusal;
  EXPECT_EQ(h->replies[0].request_id, 77);
  const auto k = h->bridge->transport().counters();
  EXPECT_EQ(k.bad_fragment, 3U);
  EXPECT_EQ(k.oversized, 1U);
  EXPECT_EQ(k.truncated, 1U);
  EXPECT_EQ(k.channel_unterminated, 1U);
  EXPECT_EQ(k.channel_too_long, 1U);
  EXPECT_EQ(k.bad_magic, 1U);
  h->bridge->publish_stats();
  for (int i = 0; i < 50 && stats.empty(); ++i) client->handle_timeout(100);
  ASSERT_EQ(stats.size(), 1U);
  std::map<std::string, std::int64_t> named;
  for (int i = 0; i < stats[0].n_transport; ++i)
    named[stats[0].transport_counter[std::size_t(i)]] = stats[0].transport_count[std::size_t(i)];
  EXPECT_EQ(named["bad_fragment"], 3);
  EXPECT_EQ(named["bad_magic"], 1);
  EXPECT_GE(named["messages"], 1);
}

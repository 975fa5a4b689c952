// Hostile datagrams into our udpm receiver (issue 22, "The PLC survives its
// HMI network"): each is counted by its reason and dropped, nothing is
// allocated for a claimed size above the bound, and a valid message from
// the same sender afterwards is still received. The checks named are the
// ones liblcm 1.3.1's lcm_udpm.c lacks or gets wrong (line numbers of
// v1.3.1). In memory: no socket (the same datagrams over the network:
// test_hmi_udpm_interop.cpp).
#include <gtest/gtest.h>

#include <optional>

#include "plc/hmi/udpm_receiver.hpp"
#include "udpm_test_datagrams.hpp"

using namespace plc::hmi;
using namespace plctest::udpm;

namespace {

struct Rx {
  explicit Rx(UdpmLimits l = {}) : r(l, [](std::string_view c) { return c != "NOBODY"; }) {}
  UdpmReceiver r;
  std::optional<Bytes> take(const Bytes& d, std::uint64_t sender = 1, std::int64_t now_us = 0) {
    auto m = r.take(d, sender, now_us, 0);
    if (!m) return std::nullopt;
    return Bytes(m->data.begin(), m->data.end());
  }
  // A valid short and a valid fragmented message from `sender` both arrive.
  void expect_still_receives(std::uint64_t sender = 1, std::uint32_t seqno = 500) {
    const Bytes small = pattern(100, 1);
    EXPECT_EQ(take(lc02(seqno, "PLC_CMD", small), sender), small);
    const Bytes big = pattern(150000, 2);
    const auto d = encode("PLC_CMD", big, seqno + 1);
    std::optional<Bytes> got;
    for (const auto& x : d) got = take(x, sender);
    EXPECT_EQ(got, big);
  }
  const TransportCounters& c() const { return r.counters(); }
  void expect_datagrams_add_up() const {
    const auto& k = c();
    EXPECT_EQ(k.datagrams, k.short_ok + k.fragment_ok + k.unsubscribed + k.dropped());
  }
};

}  // namespace

// The datagram of the issue: fragment 0, msg_size 64, fragment_offset
// 0xFFFFFFF0, 32 bytes. liblcm: 0xFFFFFFF0 + 32 wraps to 16 <= 64, memcpy
// 4 GiB past the buffer (lcm_udpm.c:316, 324): SIGSEGV in its receive
// thread. Here: offset > msg_size, a bad fragment, nothing kept.
TEST(HmiUdpmHostile, WrappingFragmentOffsetIsABadFragmentNotAWrite) {
  Rx rx;
  const Bytes d = wrapping_offset_fragment();
  ASSERT_EQ(d.size(), 60U);  // "One 60-byte UDP datagram stops the PLC"
  EXPECT_FALSE(rx.take(d));
  EXPECT_EQ(rx.c().bad_fragment, 1U);
  EXPECT_EQ(rx.r.reassemblies(), 0U);
  // The same wrap on a later fragment of a message in progress, and an
  // offset inside msg_size whose end passes it.
  const Bytes first = pattern(40000);
  EXPECT_FALSE(rx.take(lc03(9, 100000, 0, 0, 3, "PLC_CMD", first)));
  EXPECT_FALSE(rx.take(lc03(9, 100000, 0xFFFFFFF0U, 1, 3, "", Bytes(32, 0x42))));
  EXPECT_FALSE(rx.take(lc03(9, 100000, 99990, 2, 3, "", Bytes(11, 0x43))));
  EXPECT_EQ(rx.c().bad_fragment, 3U);
  rx.expect_still_receives();
  rx.expect_datagrams_add_up();
}

// Shorter than the 4-byte magic, the 8-byte LC02 header or the 20-byte LC03
// header (liblcm: frag_size = sz - 20 wraps for an LC03 under 20 bytes,
// lcm_udpm.c:255).
TEST(HmiUdpmHostile, TruncatedHeadersAreCounted) {
  Rx rx;
  const Bytes s = lc02(1, "PLC_CMD", {});
  const Bytes f = lc03(1, 10, 0, 0, 1, "PLC_CMD", Bytes(10, 1));
  for (std::size_t n = 0; n < 8; ++n) EXPECT_FALSE(rx.take(Bytes(s.begin(), s.begin() + long(n))));
  for (std::size_t n = 4; n < 20; ++n) EXPECT_FALSE(rx.take(Bytes(f.begin(), f.begin() + long(n))));
  EXPECT_EQ(rx.c().truncated, 8U + 16U);
  rx.expect_still_receives();
  rx.expect_datagrams_add_up();
}

// msg_size above the bound (4 MiB) up to 2^32-1: refused before anything
// is allocated (liblcm allocates up to 256 MiB per sender, udpm_util.c:22).
TEST(HmiUdpmHostile, HugeMsgSizeIsRefusedWithoutAllocating) {
  Rx rx;
  for (std::uint32_t size : {(1U << 22) + 1, 1U << 28, 0xFFFFFFFFU})
    EXPECT_FALSE(rx.take(lc03(2, size, 0, 0, 100, "PLC_CMD", Bytes(16, 0))));
  EXPECT_EQ(rx.c().oversized, 3U);
  EXPECT_EQ(rx.r.reassemblies(), 0U);
  EXPECT_EQ(rx.r.reassembly_bytes(), 0U);
  rx.expect_still_receives();
  rx.expect_datagrams_add_up();
}

// n_fragments 0 and fragment_no >= n_fragments are bad fragments (liblcm
// reads neither: with n_fragments 0 its fragments_remaining counts down
// from 0 and wraps, lcm_udpm.c:327); n_fragments 65535 on a small message
// holds its bookkeeping within the bound and never completes falsely.
TEST(HmiUdpmHostile, FragmentCountsOutOfRange) {
  Rx rx;
  EXPECT_FALSE(rx.take(lc03(3, 32, 0, 0, 0, "PLC_CMD", Bytes(32, 0))));
  EXPECT_FALSE(rx.take(lc03(3, 32, 0, 2, 2, "", Bytes(16, 0))));
  EXPECT_FALSE(rx.take(lc03(3, 32, 0, 65535, 65535, "", Bytes(16, 0))));
  EXPECT_EQ(rx.c().bad_fragment, 3U);
  EXPECT_FALSE(rx.take(lc03(4, 32, 0, 0, 65535, "PLC_CMD", Bytes(32, 0))));
  EXPECT_EQ(rx.r.reassemblies(), 1U);
  EXPECT_LE(rx.r.reassembly_bytes(), 32U + 65535U / 8 + 8 + 65535U * 8);
  EXPECT_EQ(rx.c().messages, 0U);  // every byte is there, but 65534 fragments are missing
  rx.expect_still_receives();      // a new message abandons it
  EXPECT_EQ(rx.c().reassembly_abandoned, 1U);
  rx.expect_datagrams_add_up();
}

// A fragment received twice is dropped once seen (liblcm counts it again:
// a message "completes" with a fragment missing, lcm_udpm.c:327-329); the
// message still completes, right, when the missing one comes.
TEST(HmiUdpmHostile, DuplicateFragmentsAreDroppedAndTheMessageStaysRight) {
  Rx rx;
  const Bytes payload = pattern(200000, 5);
  const auto d = encode("PLC_VALUES", payload, 11);
  ASSERT_EQ(d.size(), 4U);
  EXPECT_FALSE(rx.take(d[0]));
  EXPECT_FALSE(rx.take(d[1]));
  EXPECT_FALSE(rx.take(d[1]));
  EXPECT_FALSE(rx.take(d[0]));
  EXPECT_FALSE(rx.take(d[2]));
  EXPECT_EQ(rx.c().duplicate_fragment, 2U);
  EXPECT_EQ(rx.take(d[3]), payload);
  rx.expect_still_receives();
  rx.expect_datagrams_add_up();
}

// Fragments whose pieces overlap (so some other byte is never written) are
// not a message: the complete set is dropped and counted.
TEST(HmiUdpmHostile, OverlappingFragmentsAreNotAMessage) {
  Rx rx;
  EXPECT_FALSE(rx.take(lc03(12, 100, 0, 0, 3, "PLC_CMD", Bytes(50, 1))));
  EXPECT_FALSE(rx.take(lc03(12, 100, 40, 1, 3, "", Bytes(30, 2))));  // 40..70 overlaps 0..50
  EXPECT_FALSE(rx.take(lc03(12, 100, 80, 2, 3, "", Bytes(20, 3))));  // 70..80 never written
  EXPECT_EQ(rx.c().overlapping_fragments, 1U);
  EXPECT_EQ(rx.c().messages, 0U);
  EXPECT_EQ(rx.r.reassemblies(), 0U);
  rx.expect_still_receives();
  rx.expect_datagrams_add_up();
}

// A channel without its NUL inside the datagram (liblcm: strlen reads on,
// lcm_udpm.c:279 and 373), or longer than 63 characters; 63 is fine.
TEST(HmiUdpmHostile, ChannelWithoutNulOrTooLong) {
  Rx rx;
  Bytes no_nul = lc02(1, "PLC_CMD", {});
  no_nul.pop_back();
  EXPECT_FALSE(rx.take(no_nul));
  Bytes frag_no_nul = lc03(1, 10, 0, 0, 1, "PLC_CMD", {});
  frag_no_nul.pop_back();
  EXPECT_FALSE(rx.take(frag_no_nul));
  EXPECT_EQ(rx.c().channel_unterminated, 2U);
  const std::string c64(64, 'A'), c63(63, 'A');
  EXPECT_FALSE(rx.take(lc02(2, c64, {1, 2})));
  EXPECT_FALSE(rx.take(lc03(3, 2, 0, 0, 1, c64, {1, 2})));
  Bytes long_no_nul = lc02(4, std::string(200, 'B'), {});
  long_no_nul.pop_back();
  EXPECT_FALSE(rx.take(long_no_nul));
  EXPECT_EQ(rx.c().channel_too_long, 3U);
  EXPECT_EQ(rx.take(lc02(5, c63, {1, 2})), Bytes({1, 2}));
  rx.expect_still_receives();
  rx.expect_datagrams_add_up();
}

// Neither LC02 nor LC03; a fragment of a message whose fragment 0 never
// came; a message nobody subscribes to (ignored, no reassembly).
TEST(HmiUdpmHostile, BadMagicOrphanFragmentsAndUnsubscribedChannels) {
  Rx rx;
  EXPECT_FALSE(rx.take({'L', 'C', '0', '1', 0, 0, 0, 0, 'X', 0}));
  EXPECT_EQ(rx.c().bad_magic, 1U);
  EXPECT_FALSE(rx.take(lc03(6, 100, 50, 1, 2, "", Bytes(50, 1))));
  EXPECT_EQ(rx.c().orphan_fragment, 1U);
  EXPECT_FALSE(rx.take(lc02(7, "NOBODY", {1})));
  EXPECT_FALSE(rx.take(lc03(8, 100000, 0, 0, 2, "NOBODY", Bytes(1000, 1))));
  EXPECT_EQ(rx.c().unsubscribed, 2U);
  EXPECT_EQ(rx.r.reassemblies(), 0U);
  rx.expect_still_receives();
  rx.expect_datagrams_add_up();
}

// Reassembly state is bounded: many senders each starting a large message
// never hold more than max_senders reassemblies or max_reassembly_bytes;
// the least recently fed is evicted (counted), a stale one first.
TEST(HmiUdpmHostile, ReassemblyStateIsBoundedInSendersAndBytes) {
  UdpmLimits l;
  l.max_message_bytes = 1 << 20;
  l.max_senders = 8;
  l.max_reassembly_bytes = (3 << 20) + 4096;  // three 1 MiB messages and their bookkeeping
  l.reassembly_timeout_us = 1'000'000;
  Rx rx(l);
  for (std::uint64_t sender = 1; sender <= 200; ++sender) {
    EXPECT_FALSE(rx.take(lc03(1, 1 << 20, 0, 0, 17, "PLC_CMD", Bytes(1000, 1)), sender,
                         std::int64_t(sender)));
    EXPECT_LE(rx.r.reassemblies(), 3U);
    EXPECT_LE(rx.r.reassembly_bytes(), l.max_reassembly_bytes);
  }
  EXPECT_EQ(rx.c().reassembly_evicted, 197U);
  // Small messages: the sender bound holds.
  for (std::uint64_t sender = 1000; sender < 1100; ++sender) {
    EXPECT_FALSE(rx.take(lc03(1, 200, 0, 0, 2, "PLC_CMD", Bytes(100, 1)), sender, 300));
    EXPECT_LE(rx.r.reassemblies(), 8U);
  }
  // 2 s later every one is stale: the next start evicts them all first.
  const auto evicted = rx.c().reassembly_evicted;
  EXPECT_FALSE(rx.take(lc03(1, 200, 0, 0, 2, "PLC_CMD", Bytes(100, 1)), 5000, 2'000'300));
  EXPECT_EQ(rx.c().reassembly_evicted, evicted + 8);
  EXPECT_EQ(rx.r.reassemblies(), 1U);
  // A fragment for an evicted message is an orphan.
  EXPECT_FALSE(rx.take(lc03(1, 200, 100, 1, 2, "", Bytes(100, 1)), 1099, 2'000'400));
  EXPECT_EQ(rx.c().orphan_fragment, 1U);
  rx.expect_datagrams_add_up();
}

// Random bytes, and random bytes behind a valid magic: no crash, every
// datagram counted once, and valid messages still get through.
TEST(HmiUdpmHostile, RandomDatagramsAreCountedAndDropped) {
  Rx rx;
  std::uint32_t x = 2463534242U;
  auto next = [&x] {
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return x;
  };
  for (int i = 0; i < 20000; ++i) {
    Bytes d(next() % 200);
    for (auto& b : d) b = std::uint8_t(next());
    if (d.size() >= 4 && i % 3 != 0)
      udpm::put_u32(d.data(), i % 3 == 1 ? udpm::kMagicShort : udpm::kMagicFragment);
    if (d.size() >= 20 && i % 3 == 2 && i % 2 == 0)
      d[16] = d[17] = 0;  // fragment 0: parse its channel
    (void)rx.take(d, next() % 16, i);
  }
  EXPECT_EQ(rx.c().datagrams, 20000U);
  EXPECT_GT(rx.c().bad_magic, 0U);
  EXPECT_GT(rx.c().bad_fragment + rx.c().oversized, 0U);
  rx.expect_datagrams_add_up();
  rx.expect_still_receives(3, 7);
  rx.expect_datagrams_add_up();
}

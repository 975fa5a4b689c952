// Our udpm encoder and receiver against LCM's wire format as liblcm 1.3.1
// writes it (issue 22): known-answer datagrams written by hand from
// lcm/udpm_util.h and lcm_udpm.c (lcm_udpm_publish), the short/fragment
// boundary (LCM_SHORT_MESSAGE_MAX_SIZE 65499, LCM_FRAGMENT_MAX_PAYLOAD
// 65487), and encode -> receive round trips in any fragment order. The
// interop tests (test_hmi_udpm_interop.cpp) check the same against liblcm
// itself on the wire.
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>

#include "plc/hmi/udpm_receiver.hpp"
#include "udpm_test_datagrams.hpp"

using namespace plc::hmi;
using namespace plctest::udpm;

namespace {

// A receiver that wants every channel and keeps what it delivers.
struct Rx {
  UdpmReceiver r{UdpmLimits{}, [](std::string_view) { return true; }};
  std::optional<std::pair<std::string, Bytes>> take(const Bytes& d, std::uint64_t sender = 1,
                                                    std::int64_t now_us = 0) {
    auto m = r.take(d, sender, now_us, 1234);
    if (!m) return std::nullopt;
    return std::make_pair(std::string(m->channel), Bytes(m->data.begin(), m->data.end()));
  }
};

}  // namespace

// LC02 (lcm2_header_short_t): magic "LC02", seqno, channel, NUL, payload.
TEST(HmiUdpmWire, ShortMessageKnownAnswerLc02) {
  const Bytes expected = {0x4C, 0x43, 0x30, 0x32,                       // "LC02"
                          0x01, 0x02, 0x03, 0x04,                       // seqno
                          'P',  'L',  'C',  '_',  'C', 'M', 'D', 0x00,  // channel
                          0xDE, 0xAD, 0xBE, 0xEF};                      // payload
  const auto d = encode("PLC_CMD", {0xDE, 0xAD, 0xBE, 0xEF}, 0x01020304);
  ASSERT_EQ(d.size(), 1U);
  EXPECT_EQ(d[0], expected);
  Rx rx;
  const auto m = rx.take(expected);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->first, "PLC_CMD");
  EXPECT_EQ(m->second, Bytes({0xDE, 0xAD, 0xBE, 0xEF}));
}

// LC03 (lcm2_header_long_t): 70,000 bytes on PLC_DESC need 70,009 with the
// channel and its NUL: two fragments of at most 65,487 after the header;
// fragment 0 carries the channel and 65,478 payload bytes (0xFFC6), fragment
// 1 the other 4,522 from offset 0xFFC6.
TEST(HmiUdpmWire, FragmentedMessageKnownAnswerLc03) {
  const Bytes payload = pattern(70000);
  const auto d = encode("PLC_DESC", payload, 7);
  ASSERT_EQ(d.size(), 2U);
  Bytes head0 = {0x4C, 0x43, 0x30, 0x33,  // "LC03"
                 0x00, 0x00, 0x00, 0x07,  // seqno
                 0x00, 0x01, 0x11, 0x70,  // msg_size 70000
                 0x00, 0x00, 0x00, 0x00,  // fragment_offset 0
                 0x00, 0x00,              // fragment_no 0
                 0x00, 0x02,              // n_fragments 2
                 'P',  'L',  'C',  '_',  'D', 'E', 'S', 'C', 0x00};
  const Bytes head1 = {0x4C, 0x43, 0x30, 0x33, 0x00, 0x00, 0x00, 0x07, 0x00, 0x01,
                       0x11, 0x70, 0x00, 0x00, 0xFF, 0xC6, 0x00, 0x01, 0x00, 0x02};
  ASSERT_EQ(d[0].size(), 20U + 9U + 65478U);  // 65507: the largest IPv4 UDP payload
  ASSERT_EQ(d[1].size(), 20U + 4522U);
  EXPECT_TRUE(std::equal(head0.begin(), head0.end(), d[0].begin()));
  EXPECT_TRUE(std::equal(payload.begin(), payload.begin() + 65478, d[0].begin() + 29));
  EXPECT_TRUE(std::equal(head1.begin(), head1.end(), d[1].begin()));
  EXPECT_TRUE(std::equal(payload.begin() + 65478, payload.end(), d[1].begin() + 20));
  // The hand-written form, fed to the receiver, is the message again.
  Rx rx;
  EXPECT_FALSE(rx.take(
      lc03(7, 70000, 0, 0, 2, "PLC_DESC", Bytes(payload.begin(), payload.begin() + 65478))));
  const auto m =
      rx.take(lc03(7, 70000, 0xFFC6, 1, 2, "", Bytes(payload.begin() + 65478, payload.end())));
  ASSERT_TRUE(m);
  EXPECT_EQ(m->first, "PLC_DESC");
  EXPECT_EQ(m->second, payload);
}

// lcm_udpm_publish: short while channel + NUL + payload <= 65499, else
// fragments; no channel over 63 characters; at most 65535 fragments.
TEST(HmiUdpmWire, ShortFragmentBoundaryAndLimitsAsLiblcm) {
  EXPECT_EQ(udpm::datagram_count("C", 65497), 1U);  // 2 + 65497 = 65499
  EXPECT_EQ(udpm::datagram_count("C", 65498), 2U);
  const auto at_limit = encode("C", pattern(65497), 0);
  ASSERT_EQ(at_limit.size(), 1U);
  EXPECT_EQ(at_limit[0].size(), 65507U);
  const auto past = encode("C", pattern(65498), 0);
  ASSERT_EQ(past.size(), 2U);
  EXPECT_EQ(udpm::get_u32(past[0].data()), udpm::kMagicFragment);
  EXPECT_EQ(past[0].size(), 65507U);                   // 20 + "C\0" + 65485
  EXPECT_EQ(past[1].size(), 20U + (65498U - 65485U));  // the remaining 13
  EXPECT_EQ(udpm::datagram_count(std::string(63, 'x'), 0), 1U);
  EXPECT_EQ(udpm::datagram_count(std::string(64, 'x'), 0), 0U);
  EXPECT_EQ(udpm::datagram_count("", 65535ULL * 65487 - 1), 65535U);
  EXPECT_EQ(udpm::datagram_count("", 65535ULL * 65487), 0U);
}

// Encode, then receive in the order sent, reversed, and with a fragment of
// another sender between: the same channel and bytes come out once.
TEST(HmiUdpmWire, EncodeThenReceiveInAnyFragmentOrderGivesTheSameBytes) {
  for (const std::size_t size : {0UL, 1UL, 1000UL, 65490UL, 200000UL, 400000UL}) {
    const Bytes payload = pattern(size, std::uint8_t(size));
    auto d = encode("PLC_VALUES", payload, std::uint32_t(size));
    for (int order = 0; order < 2; ++order) {
      if (order == 1) std::reverse(d.begin() + 1, d.end());  // fragment 0 first, the rest reversed
      Rx rx;
      std::optional<std::pair<std::string, Bytes>> got;
      for (std::size_t k = 0; k < d.size(); ++k) {
        if (k == 1) {  // another sender's message begins
          EXPECT_FALSE(rx.take(d[0], 99));
        }
        auto m = rx.take(d[k]);
        EXPECT_TRUE(!m || k + 1 == d.size()) << "complete before its last fragment";
        if (m) got = m;
      }
      ASSERT_TRUE(got) << size;
      EXPECT_EQ(got->first, "PLC_VALUES");
      EXPECT_EQ(got->second, payload) << size;
      EXPECT_EQ(rx.r.counters().messages, 1U);
      EXPECT_EQ(rx.r.counters().dropped(), 0U);
    }
  }
}

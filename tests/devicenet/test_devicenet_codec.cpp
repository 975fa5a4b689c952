// The DeviceNet codec against toyo-vf66-devicenet.md §1.4 (identifier table,
// explicit header/service, fragmentation) and §11.1 (error response), and
// fieldbus-masters.md §2 (duplicate MAC ID check message).
#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "plc/devicenet/explicit_frame.hpp"
#include "plc/devicenet/identifiers.hpp"
#include "plc/devicenet/startup_writes.hpp"
#include "plc/io/model_params.hpp"

using namespace plc::devicenet;
using plc::can::Frame;

// §1.4 table "CAN id base": Group 1 msg 0xC..0xF -> 0x300/0x340/0x380/0x3C0;
// Group 2 = 0x400 | MAC << 3 | msg.
TEST(Identifiers, Section1_4_TableBases) {
  EXPECT_EQ(group1_id(kG1MulticastPollResponse, 0), 0x300);
  EXPECT_EQ(group1_id(kG1ChangeOfState, 0), 0x340);
  EXPECT_EQ(group1_id(kG1BitStrobeResponse, 0), 0x380);
  EXPECT_EQ(group1_id(kG1PollResponse, 0), 0x3C0);
  EXPECT_EQ(group1_id(kG1PollResponse, 5), 0x3C5);
  EXPECT_EQ(group2_id(0, kG2BitStrobe), 0x400);
  // MAC 5: explicit request 0x42C, response 0x42B, poll 0x42D,
  // unconnected 0x42E, dup MAC 0x42F.
  EXPECT_EQ(group2_id(5, kG2ExplicitResponse), 0x42B);
  EXPECT_EQ(group2_id(5, kG2ExplicitRequest), 0x42C);
  EXPECT_EQ(group2_id(5, kG2Poll), 0x42D);
  EXPECT_EQ(group2_id(5, kG2Unconnected), 0x42E);
  EXPECT_EQ(group2_id(5, kG2DupMac), 0x42F);
  EXPECT_EQ(group2_id(63, kG2DupMac), 0x5FF);
}

TEST(Identifiers, DecodeRoundTripsEveryGroup1And2Identifier) {
  for (std::uint8_t mac = 0; mac <= kMaxMac; ++mac) {
    for (std::uint8_t m = 0; m < 8; ++m) {
      const auto id = decode_id(group2_id(mac, m));
      ASSERT_TRUE(id);
      EXPECT_EQ(id->group, 2);
      EXPECT_EQ(id->mac, mac);
      EXPECT_EQ(id->msg, m);
    }
    for (std::uint8_t m = 0; m < 16; ++m) {
      const auto id = decode_id(group1_id(m, mac));
      ASSERT_TRUE(id);
      EXPECT_EQ(id->group, 1);
      EXPECT_EQ(id->mac, mac);
      EXPECT_EQ(id->msg, m);
    }
  }
  EXPECT_FALSE(decode_id(0x7F0));  // invalid identifiers
  EXPECT_FALSE(decode_id(0x800));
  EXPECT_EQ(decode_id(0x7C0)->group, 4);
  EXPECT_EQ(decode_id(0x600)->group, 3);
}

// §1.4 [std]: header = Frag | XID | MAC; Allocate = [hdr][0x4B][03][01][choice][master].
TEST(ExplicitFrame, AllocateRequestIsOneFrameOnTheUnconnectedPort) {
  const std::uint8_t msg[] = {0x4B, 0x03, 0x01, 0x03, 0x00};
  ExplicitFrames out;
  ASSERT_TRUE(build_explicit(group2_id(5, kG2Unconnected), 0, false, msg, out));
  ASSERT_EQ(out.count, 1u);
  const Frame& f = out.frames[0];
  EXPECT_EQ(f.id, 0x42Eu);
  EXPECT_EQ(f.len, 6);
  const std::uint8_t expect[] = {0x00, 0x4B, 0x03, 0x01, 0x03, 0x00};
  EXPECT_TRUE(std::equal(std::begin(expect), std::end(expect), f.data.begin()));
}

// §1.4 [std]: an explicit message longer than 7 bytes (after the header) is
// fragmented: [hdr|0x80][type<<6|count][6 bytes]..., first 0, middle 1, last 2.
TEST(ExplicitFrame, FragmentationFirstMiddleLastAndReassembly) {
  std::vector<std::uint8_t> msg(15);
  std::iota(msg.begin(), msg.end(), 0x10);
  ExplicitFrames out;
  ASSERT_TRUE(build_explicit(0x42C, 1, false, msg, out));
  ASSERT_EQ(out.count, 3u);
  EXPECT_EQ(out.frames[0].data[0], 0x81);
  EXPECT_EQ(out.frames[0].data[1], 0x00);  // first, count 0
  EXPECT_EQ(out.frames[1].data[1], 0x41);  // middle, count 1
  EXPECT_EQ(out.frames[2].data[1], 0x82);  // last, count 2
  EXPECT_EQ(out.frames[0].len, 8);
  EXPECT_EQ(out.frames[2].len, 2 + 3);
  ExplicitReassembler r;
  EXPECT_EQ(r.take(out.frames[0]), ExplicitReassembler::Result::FragmentAck);
  EXPECT_EQ(r.ack_count(), 0);
  // A repeated first fragment starts the message over.
  ASSERT_EQ(r.take(out.frames[0]), ExplicitReassembler::Result::FragmentAck);
  EXPECT_EQ(r.take(out.frames[1]), ExplicitReassembler::Result::FragmentAck);
  EXPECT_EQ(
      r.take(out.frames[1]),
      ExplicitReassembler::Result::FragmentAck);  // a repeat (ack lost): acked again, not appended
  ASSERT_EQ(r.take(out.frames[2]), ExplicitReassembler::Result::LastFragment);
  EXPECT_EQ(r.ack_count(), 2);
  ASSERT_EQ(r.message().size(), msg.size());
  EXPECT_TRUE(std::equal(msg.begin(), msg.end(), r.message().begin()));
}

TEST(ExplicitFrame, AckLayoutAndOutOfSequenceFragmentsAreDropped) {
  const Frame ack = explicit_ack(0x42B, 1, false, 2, kAckSuccess);
  EXPECT_EQ(ack.len, 3);
  EXPECT_EQ(ack.data[0], 0x81);
  EXPECT_EQ(ack.data[1], 0xC2);  // type 3 (ack), count 2
  EXPECT_EQ(ack.data[2], 0x00);
  ExplicitReassembler r;
  EXPECT_EQ(r.take(ack), ExplicitReassembler::Result::AckReceived);
  EXPECT_EQ(r.ack_count(), 2);
  // A middle fragment without a first one, and a gap in the count.
  Frame mid;
  mid.id = 0x42C;
  mid.len = 4;
  mid.data = {0x81, 0x41, 1, 2};
  EXPECT_EQ(r.take(mid), ExplicitReassembler::Result::Bad);
  Frame first = mid;
  first.data[1] = 0x00;
  EXPECT_EQ(r.take(first), ExplicitReassembler::Result::FragmentAck);
  Frame gap = mid;
  gap.data[1] = 0x43;
  EXPECT_EQ(r.take(gap), ExplicitReassembler::Result::Bad);
  Frame shortf;
  shortf.len = 1;
  EXPECT_EQ(r.take(shortf), ExplicitReassembler::Result::Bad);
}

// §11.1 Table 5.2: Error Response = service 0x94, general code, additional (0xFF none).
TEST(ExplicitFrame, ErrorResponseLayout) {
  const std::uint8_t msg[] = {0x94, 0x14, 0xFF};
  ExplicitFrames out;
  ASSERT_TRUE(build_explicit(0x42B, 1, false, msg, out));
  ASSERT_EQ(out.count, 1u);
  EXPECT_EQ(out.frames[0].len, 4);
  EXPECT_EQ(out.frames[0].data[1], 0x94);
  EXPECT_EQ(out.frames[0].data[2], 0x14);
}

// §1.4 [std]: I/O above 8 bytes: [type<<6|count][7 data bytes], no acks.
// Input assembly 120 (12 bytes) = 2 fragments.
TEST(IoFrame, TwelveBytesAreTwoFragments) {
  std::vector<std::uint8_t> d(12);
  std::iota(d.begin(), d.end(), 1);
  IoFrames out;
  ASSERT_TRUE(build_io(0x3C5, d, out));
  ASSERT_EQ(out.count, 2u);
  EXPECT_EQ(out.frames[0].data[0], 0x00);
  EXPECT_EQ(out.frames[0].len, 8);
  EXPECT_EQ(out.frames[1].data[0], 0x81);
  EXPECT_EQ(out.frames[1].len, 6);
  IoReassembler r(12);
  EXPECT_EQ(r.take(out.frames[0]), IoReassembler::Result::Partial);
  ASSERT_EQ(r.take(out.frames[1]), IoReassembler::Result::Complete);
  EXPECT_TRUE(std::equal(d.begin(), d.end(), r.data().begin()));
  // 8 bytes fit one frame unfragmented (instances 100/140).
  ASSERT_TRUE(build_io(0x42D, std::span(d).first(8), out));
  EXPECT_EQ(out.count, 1u);
  EXPECT_EQ(out.frames[0].len, 8);
  // A last fragment without a first is dropped.
  IoReassembler r2(12);
  EXPECT_EQ(r2.take(out.frames[0]), IoReassembler::Result::Bad);  // 0x01 = first with count 1
}

// fieldbus-masters.md §2: [R/R | port][vendor LE][serial LE 32].
TEST(DupMac, MessageLayout) {
  const Frame f = build_dup_mac(5, {true, 0, 560, 0x11223344});
  EXPECT_EQ(f.id, 0x42Fu);
  ASSERT_EQ(f.len, 7);
  const std::uint8_t expect[] = {0x80, 0x30, 0x02, 0x44, 0x33, 0x22, 0x11};
  EXPECT_TRUE(std::equal(std::begin(expect), std::end(expect), f.data.begin()));
  const auto m = parse_dup_mac(f);
  ASSERT_TRUE(m);
  EXPECT_TRUE(m->response);
  EXPECT_EQ(m->vendor, 560);
  EXPECT_EQ(m->serial, 0x11223344u);
  Frame s = f;
  s.len = 6;
  EXPECT_FALSE(parse_dup_mac(s));
}

TEST(StartupWrites, ParsesAndRejectsWithTheKey) {
  const auto w = parse_startup_writes("0x2A/1/22=03; 5/2/9 = 3200");
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0].cls, 0x2A);
  EXPECT_EQ(w[0].attribute, 22);
  EXPECT_EQ(w[0].data, std::vector<std::uint8_t>{3});
  EXPECT_EQ(w[1].data, (std::vector<std::uint8_t>{0x32, 0x00}));
  EXPECT_TRUE(parse_startup_writes("").empty());
  for (const char* bad : {"0x2A/1=03", "0x2A/1/22", "0x2A/1/22=3", "0x2A/1/300=00", "x/1/1=00"}) {
    try {
      parse_startup_writes(bad);
      ADD_FAILURE() << bad;
    } catch (const plc::io::ParamError& e) {
      EXPECT_EQ(e.key, "startup");
    }
  }
}

// FDL telegrams (IEC 61158-4-3 / EN 50170 vol. 2 §4.2: SD1, SD2, SD3, SD4,
// SC, FCS, address extension) against byte sequences from outside this
// project, never our own encoder:
//  [R] Rahix/profirust, tests/real_hw.rs (phy_test) and src/fdl/telegram.rs:
//      an FDL status request from master 2 to a WAGO 750-343 at address 34,
//      and that station's answer, as received from real hardware over a USB
//      RS-485 adapter at 19.2 kbit/s.
//  [P] pyprofibus (mbuesch/pyprofibus e7c9815, GPL-2.0+): the bytes its own
//      encoder (FdlTelegram.getRawData() of its DpTelegram_* classes and of
//      its dummy slave's answers) produces for master 2 and slave 8; run by
//      hand in a session, the bytes copied here (none of its code).
//  [M] the Kipp & Zonen COMBILOG 1022 hardware manual, table 11.11, and the
//      ABB FPBA-01 user manual, figure 13: SD1/SD2/SD3 values, LE = 3 +
//      data unit (4..249), ED 16h.
// Each test decodes the outside bytes field by field and encodes the decoded
// telegram back to the same bytes.
#include <gtest/gtest.h>

#include <vector>

#include "plc/profibus/fdl/deframer.hpp"
#include "plc/profibus/fdl/telegram.hpp"

using namespace plc::profibus::fdl;

namespace {

using Bytes = std::vector<std::uint8_t>;

Telegram decode_ok(const Bytes& b) {
  Telegram t;
  const DecodeResult r = decode(b, t);
  EXPECT_EQ(r.status, DecodeStatus::Ok) << r.why;
  EXPECT_EQ(r.consumed, b.size());
  return t;
}

Bytes encode_bytes(const Telegram& t) {
  std::array<std::uint8_t, kMaxTelegram> out{};
  const std::size_t n = encode(t, out);
  return {out.begin(), out.begin() + n};
}

}  // namespace

// [R]: 10 22 02 49 6D 16 and 10 02 22 00 24 16 (real hardware).
TEST(FdlTelegram, Sd1FdlStatusRequestAndAnswerOfARealStation_Profirust) {
  const Bytes req{0x10, 0x22, 0x02, 0x49, 0x6D, 0x16};
  const Telegram q = decode_ok(req);
  EXPECT_EQ(q.format, Format::Sd1);
  EXPECT_EQ(q.da, 34);
  EXPECT_EQ(q.sa, 2);
  EXPECT_TRUE(q.request());
  EXPECT_EQ(q.function(), kReqFdlStatus);
  EXPECT_EQ(q.fc & (kFcFcb | kFcFcv), 0);
  EXPECT_EQ(encode_bytes(q), req);

  const Bytes res{0x10, 0x02, 0x22, 0x00, 0x24, 0x16};
  const Telegram a = decode_ok(res);
  EXPECT_FALSE(a.request());
  EXPECT_EQ(a.function(), kResOk);
  EXPECT_EQ(a.fc & 0x30, kStationSlave);
  EXPECT_EQ(a.da, 2);
  EXPECT_EQ(a.sa, 34);
  EXPECT_EQ(encode_bytes(a), res);
}

// [P] Slave_Diag request: SD2, DA 8|ext, SA 2|ext, FC 4D (SRD high), DSAP
// 60, SSAP 62, no data: 68 05 05 68 88 82 4D 3C 3E D1 16.
TEST(FdlTelegram, Sd2SlaveDiagRequestWithSaps_Pyprofibus) {
  const Bytes b{0x68, 0x05, 0x05, 0x68, 0x88, 0x82, 0x4D, 0x3C, 0x3E, 0xD1, 0x16};
  const Telegram t = decode_ok(b);
  EXPECT_EQ(t.format, Format::Sd2);
  EXPECT_EQ(t.da, 8);
  EXPECT_EQ(t.sa, 2);
  EXPECT_EQ(t.function(), kReqSrdHigh);
  EXPECT_EQ(t.dsap, 60);
  EXPECT_EQ(t.ssap, 62);
  EXPECT_EQ(t.length, 0);
  EXPECT_EQ(encode_bytes(t), b);
}

// [P] Set_Prm to the PR1721/31 (Ident 0x5610, WD 5 x 20, minTSDR 11, group
// 1, Lock_Req + WD_On): its FCS happens to be E5, the SC character.
TEST(FdlTelegram, Sd2SetPrmWhoseFcsIsTheScCharacter_Pyprofibus) {
  const Bytes b{0x68, 0x0C, 0x0C, 0x68, 0x88, 0x82, 0x4D, 0x3D, 0x3E,
                0x88, 0x05, 0x14, 0x0B, 0x56, 0x10, 0x01, 0xE5, 0x16};
  const Telegram t = decode_ok(b);
  EXPECT_EQ(t.dsap, 61);
  ASSERT_EQ(t.length, 7);
  EXPECT_EQ(Bytes(t.du().begin(), t.du().end()), (Bytes{0x88, 0x05, 0x14, 0x0B, 0x56, 0x10, 0x01}));
  EXPECT_EQ(encode_bytes(t), b);
}

// [P] Chk_Cfg with one and with two Cfg bytes (B7; B7 FF).
TEST(FdlTelegram, Sd2ChkCfg_Pyprofibus) {
  const Bytes one{0x68, 0x06, 0x06, 0x68, 0x88, 0x82, 0x4D, 0x3E, 0x3E, 0xB7, 0x8A, 0x16};
  Telegram t = decode_ok(one);
  EXPECT_EQ(t.dsap, 62);
  EXPECT_EQ(t.ssap, 62);
  EXPECT_EQ(t.length, 1);
  EXPECT_EQ(t.data[0], 0xB7);
  EXPECT_EQ(encode_bytes(t), one);
  const Bytes two{0x68, 0x07, 0x07, 0x68, 0x88, 0x82, 0x4D, 0x3E, 0x3E, 0xB7, 0xFF, 0x89, 0x16};
  t = decode_ok(two);
  EXPECT_EQ(t.length, 2);
  EXPECT_EQ(encode_bytes(t), two);
}

// [P] Data_Exchange of 8 output bytes: no SAPs, exactly 8 data bytes -> SD3.
TEST(FdlTelegram, Sd3DataExchangeOfEightBytes_Pyprofibus) {
  const Bytes b{0xA2, 0x08, 0x02, 0x4D, 0x00, 0x00, 0x00, 0x00, 0x12, 0x00, 0x00, 0x80, 0xE9, 0x16};
  const Telegram t = decode_ok(b);
  EXPECT_EQ(t.format, Format::Sd3);
  EXPECT_EQ(t.dsap, -1);
  EXPECT_EQ(t.length, 8);
  EXPECT_EQ(t.data[4], 0x12);
  EXPECT_EQ(t.data[7], 0x80);
  EXPECT_EQ(encode_bytes(t), b);
  // And the answer of 8 input bytes, FC 08 (DL): A2 02 08 08 ... 32 16.
  const Bytes res{0xA2, 0x02, 0x08, 0x08, 0x00, 0x00, 0x13,
                  0x88, 0x04, 0x00, 0x81, 0x00, 0x32, 0x16};
  const Telegram a = decode_ok(res);
  EXPECT_EQ(a.function(), kResDataLow);
  EXPECT_EQ(encode_bytes(a), res);
}

// [P] the dummy slave's Slave_Diag answer: SAPs + 6 bytes = 8 -> SD3 with an
// address extension: A2 82 88 08 3E 3C 00 04 00 FF 00 00 8F 16.
TEST(FdlTelegram, Sd3SlaveDiagAnswerWithSaps_Pyprofibus) {
  const Bytes b{0xA2, 0x82, 0x88, 0x08, 0x3E, 0x3C, 0x00, 0x04, 0x00, 0xFF, 0x00, 0x00, 0x8F, 0x16};
  const Telegram t = decode_ok(b);
  EXPECT_EQ(t.format, Format::Sd3);
  EXPECT_EQ(t.dsap, 62);
  EXPECT_EQ(t.ssap, 60);
  EXPECT_EQ(t.length, 6);
  EXPECT_EQ(t.data[1], 0x04);  // Station_Status_2 bit 2, always 1
  EXPECT_EQ(t.data[3], 0xFF);  // no master yet
  EXPECT_EQ(encode_bytes(t), b);
}

// [P] Data_Exchange of 3 bytes (SD2 without SAPs) and its echo answer.
TEST(FdlTelegram, Sd2DataExchangeWithoutSaps_Pyprofibus) {
  const Bytes req{0x68, 0x06, 0x06, 0x68, 0x08, 0x02, 0x4D, 0x01, 0x02, 0x03, 0x5D, 0x16};
  EXPECT_EQ(encode_bytes(decode_ok(req)), req);
  const Bytes res{0x68, 0x06, 0x06, 0x68, 0x02, 0x08, 0x08, 0xFE, 0xFD, 0xFC, 0x09, 0x16};
  const Telegram a = decode_ok(res);
  EXPECT_EQ(a.length, 3);
  EXPECT_EQ(encode_bytes(a), res);
}

// [P] Global_Control, SDN high (FC 46) to the broadcast address 127 with
// SAPs 58/62: Freeze to group 1, Sync to all.
TEST(FdlTelegram, Sd2GlobalControlBroadcast_Pyprofibus) {
  const Bytes freeze{0x68, 0x07, 0x07, 0x68, 0xFF, 0x82, 0x46, 0x3A, 0x3E, 0x08, 0x01, 0x48, 0x16};
  Telegram t = decode_ok(freeze);
  EXPECT_EQ(t.da, kBroadcast);
  EXPECT_EQ(t.function(), kReqSdnHigh);
  EXPECT_EQ(t.dsap, 58);
  EXPECT_EQ(encode_bytes(t), freeze);
  const Bytes sync{0x68, 0x07, 0x07, 0x68, 0xFF, 0x82, 0x46, 0x3A, 0x3E, 0x20, 0x00, 0x5F, 0x16};
  t = decode_ok(sync);
  EXPECT_EQ(t.data[0], 0x20);
  EXPECT_EQ(encode_bytes(t), sync);
}

// [P] the token a single master passes to itself (DC 02 02) and the short
// acknowledgement (E5).
TEST(FdlTelegram, Sd4TokenAndShortAck_Pyprofibus) {
  const Bytes tok{0xDC, 0x02, 0x02};
  const Telegram t = decode_ok(tok);
  EXPECT_EQ(t.format, Format::Token);
  EXPECT_EQ(t.da, 2);
  EXPECT_EQ(t.sa, 2);
  EXPECT_EQ(encode_bytes(t), tok);
  const Bytes sc{0xE5};
  EXPECT_EQ(decode_ok(sc).format, Format::ShortAck);
  EXPECT_EQ(encode_bytes(make_short_ack()), sc);
}

// [M] the frame rules: a wrong FCS, LE != LEr, a missing ED, LE outside
// 4..249 and an unknown start delimiter are refused with the reason.
TEST(FdlTelegram, MalformedTelegramsAreRefusedWithTheReason) {
  Telegram t;
  Bytes b{0x10, 0x22, 0x02, 0x49, 0x6E, 0x16};
  EXPECT_EQ(decode(b, t).status, DecodeStatus::Bad);
  EXPECT_STREQ(decode(b, t).why, "frame check sequence");
  b = {0x10, 0x22, 0x02, 0x49, 0x6D, 0x17};
  EXPECT_STREQ(decode(b, t).why, "no end delimiter");
  b = {0x68, 0x05, 0x06, 0x68};
  EXPECT_STREQ(decode(b, t).why, "LE and LEr differ");
  b = {0x68, 0x03, 0x03, 0x68, 0, 0, 0, 0, 0x16};
  EXPECT_STREQ(decode(b, t).why, "LE outside 4..249");
  b = {0x68, 0xFA, 0xFA, 0x68};
  EXPECT_STREQ(decode(b, t).why, "LE outside 4..249");
  b = {0x42};
  EXPECT_STREQ(decode(b, t).why, "no start delimiter");
  // A beginning waits for the rest.
  b = {0x68, 0x05, 0x05, 0x68, 0x88};
  EXPECT_EQ(decode(b, t).status, DecodeStatus::NeedMore);
  // An extension bit without an extension byte.
  b = {0x68, 0x04, 0x04, 0x68, 0x88, 0x82, 0x4D, 0x3C};
  b.push_back(fcs({b.data() + 4, 4}));
  b.push_back(0x16);
  EXPECT_STREQ(decode(b, t).why, "address extension of SA")
      << "DA's extension takes 3C, SA's has no byte";
}

// Encoding refuses what the format cannot carry.
TEST(FdlTelegram, EncodeRefusesOversizedDataAndBadAddresses) {
  std::array<std::uint8_t, kMaxTelegram> out{};
  Telegram t = make_data(8, 2, kFcRequest | kReqSrdHigh, 60, 62);
  std::array<std::uint8_t, 245> big{};
  EXPECT_FALSE(t.set_data(big)) << "244 data bytes + 2 SAPs at most";
  EXPECT_TRUE(t.set_data(std::span(big).first(244)));
  EXPECT_EQ(encode(t, out), 4u + 3 + 246 + 2);
  t.da = 200;
  EXPECT_EQ(encode(t, out), 0u);
  t.da = 8;
  t.dsap = 64;
  EXPECT_EQ(encode(t, out), 0u);
}

// The deframer splits a byte stream (arbitrary pieces, garbage between) into
// the telegrams [R] and [P] above.
TEST(FdlDeframer, SplitsAStreamInPiecesAndResynchronisesAfterGarbage) {
  const Bytes stream{0x00, 0xFF, 0x10, 0x22, 0x02, 0x49, 0x6D, 0x16, 0xE5, 0xDC, 0x02, 0x02,
                     0x68, 0x06, 0x06, 0x68, 0x08, 0x02, 0x4D, 0x01, 0x02, 0x03, 0x5D, 0x16};
  Deframer d;
  std::vector<Format> got;
  for (std::size_t i = 0; i < stream.size(); i += 5) {
    d.push(std::span(stream).subspan(i, std::min<std::size_t>(5, stream.size() - i)));
    Telegram t;
    while (d.next(t)) got.push_back(t.format);
  }
  EXPECT_EQ(got, (std::vector<Format>{Format::Sd1, Format::ShortAck, Format::Token, Format::Sd2}));
  EXPECT_EQ(d.dropped_bytes(), 2u);
  EXPECT_EQ(d.buffered(), 0u);
}

// Crc2Cache (issue 23): CRC2 from a cached head and the consecutive-number
// tables must be the CRC2 of safety_pdu.hpp bit for bit, on the captured
// telegrams of profisafe-wire-vectors.md and on every kind of telegram
// sequence (head repeated, changed, toggled; every F-data length; numbers
// across their bytes and the 24-bit end; spec nord-profisafe.md §2.1, §2.6).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "bitwise_crc.hpp"
#include "captured_telegrams.hpp"
#include "plc/fb/safety/crc2_cache.hpp"

namespace {

using namespace plc::safety;

using plctest::profisafe::CaptureRow;
using plctest::profisafe::kCapture;
using plctest::profisafe::kCaptureCrc1;

// The capture in its order through one cache: rows 3..7 repeat the heads
// of rows 2 and 3 (same data, toggle alternating), so they come from the
// cache; a PDU built with it is the captured one, and it checks.
TEST(SafetyCrc2Cache, CapturedTelegramsInTheirOrder_RealTraffic) {
  Crc2Cache build, check;
  for (const CaptureRow& r : kCapture) {
    std::array<std::uint8_t, 12> pdu{};
    build.write_pdu(pdu, r.fdata, r.status, r.cons_nr, kCaptureCrc1);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(pdu[9 + i], r.crc2[i]) << "row " << r.cons_nr;
    EXPECT_TRUE(check.check_pdu(pdu, 8, r.cons_nr, kCaptureCrc1)) << "row " << r.cons_nr;
    EXPECT_FALSE(check.check_pdu(pdu, 8, r.cons_nr + 1, kCaptureCrc1)) << "row " << r.cons_nr;
  }
}

// The worked example of the vectors file with the bitwise reference, for a
// number in each of the tail's three bytes and at the 24-bit end.
TEST(SafetyCrc2Cache, EachNumberByteAgainstTheBitwiseReference_WireVectors) {
  Crc2Cache cache;
  const std::array<std::uint8_t, 8> d = kCapture[0].fdata;
  for (std::uint32_t cn : {0u, 1u, 0xFFu, 0x100u, 0xABCDu, 0x10000u, 0x123456u, 0xFFFFFFu}) {
    std::vector<std::uint8_t> msg{0x40};
    for (std::size_t i = d.size(); i-- > 0;) msg.push_back(d[i]);
    msg.insert(msg.end(), {static_cast<std::uint8_t>(cn), static_cast<std::uint8_t>(cn >> 8),
                           static_cast<std::uint8_t>(cn >> 16), 0x00});
    EXPECT_EQ(cache.crc2(d, 0x40, cn, 0x22FF), safety_test::bitwise_crc(0x5D6DCBu, 24, 0x22FF, msg))
        << "cons. no. " << cn;
  }
}

// 200,000 telegrams as a connection sends them: mostly the same head with
// the toggle alternating, now and then other data, another control byte,
// another CRC1 or another length (0..16 bytes: the 4-byte CRC2 above 12 is
// not cached), numbers counting on from random starts. Every CRC2 and
// every PDU equals safety_pdu.hpp's.
TEST(SafetyCrc2Cache, SameAsComputeCrc2OnEveryKindOfSequence_Spec2_1_Spec2_6) {
  std::mt19937 rng(23);
  auto pick = [&](std::uint32_t n) { return static_cast<std::uint32_t>(rng() % n); };
  Crc2Cache cache;
  std::vector<std::uint8_t> data(4);
  std::uint8_t cb = 0x02;
  std::uint16_t seed = 0x32CB;
  std::uint32_t cn = 0;
  int checked = 0;
  for (int i = 0; i < 200000; ++i) {
    switch (pick(50)) {
      case 0:
        data.resize(pick(17));
        [[fallthrough]];
      case 1:
        for (auto& b : data) b = static_cast<std::uint8_t>(rng());
        break;
      case 2:
        cb = static_cast<std::uint8_t>(rng());
        break;
      case 3:
        seed = static_cast<std::uint16_t>(rng());
        break;
      case 4:
        cn = pick(0x1000000);
        break;
      default:
        break;
    }
    cb ^= 0x20;  // the toggle bit
    cn = next_cons_nr(cn);
    const std::uint32_t want = compute_crc2(data, cb, cn, seed);
    ASSERT_EQ(cache.crc2(data, cb, cn, seed), want)
        << "telegram " << i << " length " << data.size() << " number " << cn;
    std::vector<std::uint8_t> a(pdu_size(data.size())), b(a.size());
    write_pdu(a, data, cb, cn, seed);
    cache.write_pdu(b, data, cb, cn, seed);
    ASSERT_EQ(a, b) << "telegram " << i;
    ASSERT_TRUE(cache.check_pdu(a, data.size(), cn, seed)) << "telegram " << i;
    ++checked;
  }
  EXPECT_EQ(checked, 200000);
}

// A head that differs from a cached one in a single place (one bit of any
// F-data byte, of the control byte or of CRC1, or only in its length, for
// every length the cache holds) is never taken for it: the cache packs the
// head into words, and every byte must be in them.
TEST(SafetyCrc2Cache, HeadDifferingInOnePlaceIsNotTheCachedOne_Spec2_1) {
  std::mt19937 rng(2301);
  for (std::size_t n = 0; n <= 12; ++n) {
    std::vector<std::uint8_t> base(n);
    for (auto& b : base) b = static_cast<std::uint8_t>(rng());
    const std::uint8_t cb = 0x12;
    const std::uint16_t seed = 0x4E7A;
    const std::uint32_t cn = 0x0302A1;
    auto same_as_full = [&](Crc2Cache& c, const std::vector<std::uint8_t>& d, std::uint8_t b,
                            std::uint16_t s) {
      return c.crc2(d, b, cn, s) == compute_crc2(d, b, cn, s);
    };
    for (std::size_t i = 0; i < n; ++i) {
      for (int bit = 0; bit < 8; ++bit) {
        Crc2Cache cache;
        ASSERT_TRUE(same_as_full(cache, base, cb, seed));
        auto d = base;
        d[i] ^= static_cast<std::uint8_t>(1u << bit);
        ASSERT_TRUE(same_as_full(cache, d, cb, seed)) << "length " << n << " byte " << i;
      }
    }
    for (int bit = 0; bit < 16; ++bit) {
      Crc2Cache cache;
      ASSERT_TRUE(same_as_full(cache, base, cb, seed));
      if (bit < 8 && bit != 5) {  // bit 5 (toggle) selects the other slot anyway
        ASSERT_TRUE(same_as_full(cache, base, static_cast<std::uint8_t>(cb ^ (1u << bit)), seed))
            << "length " << n << " control bit " << bit;
      }
      ASSERT_TRUE(same_as_full(cache, base, cb, static_cast<std::uint16_t>(seed ^ (1u << bit))))
          << "length " << n << " CRC1 bit " << bit;
    }
    if (n > 0) {  // the same bytes, one shorter (a trailing zero byte)
      Crc2Cache cache;
      auto d = base;
      d.back() = 0;
      ASSERT_TRUE(same_as_full(cache, d, cb, seed));
      d.pop_back();
      ASSERT_TRUE(same_as_full(cache, d, cb, seed)) << "length " << n << " -> " << n - 1;
    }
  }
}

// A cached head does not make a corrupted telegram, another number or
// another CRC1 check (spec §8.2 3), nor a PDU shorter than its length.
TEST(SafetyCrc2Cache, CheckFailsOnEveryBitFlipOtherNumberOrCrc1_Spec8_2) {
  Crc2Cache build, check;
  std::array<std::uint8_t, 8> pdu{};
  const std::array<std::uint8_t, 4> d = {1, 2, 3, 4};
  build.write_pdu(pdu, d, 0x20, 77, 0x32CB);
  ASSERT_TRUE(check.check_pdu(pdu, 4, 77, 0x32CB));  // the head is cached now
  EXPECT_FALSE(check.check_pdu(pdu, 4, 76, 0x32CB));
  EXPECT_FALSE(check.check_pdu(pdu, 4, 77, 0x32CA));
  EXPECT_FALSE(check.check_pdu(std::span<const std::uint8_t>(pdu).first(7), 4, 77, 0x32CB));
  for (std::size_t i = 0; i < pdu.size(); ++i) {
    for (int b = 0; b < 8; ++b) {
      auto bad = pdu;
      bad[i] ^= static_cast<std::uint8_t>(1u << b);
      EXPECT_FALSE(check.check_pdu(bad, 4, 77, 0x32CB)) << "byte " << i << " bit " << b;
    }
  }
  EXPECT_TRUE(check.check_pdu(pdu, 4, 77, 0x32CB));
}

}  // namespace

// The bounds-checked byte reader/writer every PROFINET decoder is built on.
#include <gtest/gtest.h>

#include <array>
#include <cstring>

#include "plc/profinet/wire.hpp"

namespace pn = plc::profinet;

TEST(WireCodec, ReaderPastTheEndFailsAndReadsZero) {
  const std::array<std::uint8_t, 3> b{0x12, 0x34, 0x56};
  pn::ByteReader r(b);
  EXPECT_EQ(r.u16(), 0x1234);
  EXPECT_FALSE(r.failed());
  EXPECT_EQ(r.u16(), 0);  // one byte left: refused, nothing consumed
  EXPECT_TRUE(r.failed());
  EXPECT_EQ(r.u8(), 0);  // stays failed
  EXPECT_EQ(r.remaining(), 0u);
}

TEST(WireCodec, ReaderLittleEndianFields) {
  const std::array<std::uint8_t, 6> b{0x34, 0x12, 0x78, 0x56, 0x34, 0x12};
  pn::ByteReader r(b);
  EXPECT_EQ(r.u16(true), 0x1234);
  EXPECT_EQ(r.u32(true), 0x12345678u);
}

TEST(WireCodec, WriterOverflowWritesNothingPastTheEnd) {
  std::array<std::uint8_t, 4> b{};
  pn::ByteWriter w(std::span<std::uint8_t>(b).first(3));
  w.u16(0xABCD);
  w.u16(0x1122);  // does not fit in the 3-byte span
  EXPECT_TRUE(w.failed());
  EXPECT_EQ(b[2], 0);
  EXPECT_EQ(b[3], 0);
}

// copy_io_bytes() (the per-frame IO data copy without a libc call) against
// memcpy for every length up to past its memcpy threshold and every
// offset of source and destination: the same bytes, nothing written
// before or after the n bytes.
TEST(WireCodec, CopyIoBytesIsMemcpy) {
  std::array<std::uint8_t, 96> src{};
  for (std::size_t i = 0; i < src.size(); ++i) src[i] = static_cast<std::uint8_t>(i * 37 + 11);
  for (std::size_t n = 0; n <= 48; ++n) {
    for (std::size_t from = 0; from < 8; ++from) {
      for (std::size_t to = 0; to < 8; ++to) {
        std::array<std::uint8_t, 96> fast{}, full{};
        fast.fill(0xA5);
        full.fill(0xA5);
        pn::copy_io_bytes(fast.data() + to, src.data() + from, n);
        std::memcpy(full.data() + to, src.data() + from, n);
        ASSERT_EQ(fast, full) << "n " << n << " from " << from << " to " << to;
      }
    }
  }
}

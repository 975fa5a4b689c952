// The recording's CRC-32 (plc/debug/crc32.hpp, slice-by-8) against the
// catalogue's check value and against boost::crc_32_type, which computed
// it before, over random streams split at random places: the stored CRCs
// of every recording must stay the same bit for bit.
#include <gtest/gtest.h>

#include <boost/crc.hpp>
#include <cstdint>
#include <random>
#include <vector>

#include "plc/debug/crc32.hpp"

using plc::debug::Crc32;

TEST(Crc32, CatalogueCheckValue) {
  // CRC-32/ISO-HDLC: check = crc("123456789") = 0xCBF43926; empty = 0.
  Crc32 c;
  EXPECT_EQ(c.checksum(), 0u);
  c.process_bytes("123456789", 9);
  EXPECT_EQ(c.checksum(), 0xCBF43926u);
  Crc32 split;  // the same in two pieces, the first shorter than a step
  split.process_bytes("123", 3);
  split.process_bytes("456789", 6);
  EXPECT_EQ(split.checksum(), 0xCBF43926u);
}

TEST(Crc32, SameAsBoostForEverySplitOfTheStream) {
  std::mt19937_64 rng(20261203);
  for (int stream = 0; stream < 200; ++stream) {
    std::vector<std::uint8_t> bytes(std::uniform_int_distribution<std::size_t>(0, 5000)(rng));
    for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
    Crc32 ours;
    boost::crc_32_type theirs;
    // Pieces of 0..40 bytes at odd offsets (a record's head is 5 bytes),
    // the running checksums compared after each, as the recorder stores them.
    for (std::size_t at = 0; at < bytes.size();) {
      const std::size_t n =
          std::min(bytes.size() - at, std::uniform_int_distribution<std::size_t>(0, 40)(rng));
      ours.process_bytes(bytes.data() + at, n);
      theirs.process_bytes(bytes.data() + at, n);
      ASSERT_EQ(ours.checksum(), theirs.checksum()) << "stream " << stream << " at " << at;
      at += n;
    }
    Crc32 whole;
    whole.process_bytes(bytes.data(), bytes.size());
    EXPECT_EQ(whole.checksum(), theirs.checksum()) << "stream " << stream;
  }
}

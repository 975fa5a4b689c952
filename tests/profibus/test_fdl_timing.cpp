// Bus timing (EN 50170 vol. 2: TSL, TSDR, TSYN, TQUI, TSET, TID1, TID2,
// TTR; the DP bus profile's defaults per baud rate) and the computed bus
// cycle. The figures are worked by hand in the comments.
#include <gtest/gtest.h>

#include "plc/profibus/fdl/timing.hpp"

using namespace plc::profibus::fdl;

TEST(FdlTiming, TenBaudRatesWithTheirProfiles) {
  EXPECT_EQ(baud_profiles().size(), 10u);
  EXPECT_EQ(baud_profile(1500000)->max_tsdr, 150);
  EXPECT_EQ(baud_profile(12000000)->tsl, 1000);
  EXPECT_EQ(baud_profile(12000000)->max_retry, 4);
  EXPECT_STREQ(baud_profile(45450)->gsd_suffix, "45.45");
  EXPECT_EQ(baud_profile(115200), nullptr);
}

// 1.5 Mbit/s, the GSD's MaxTsdr_1.5M = 150: TSL stays 300 (150 + 0 + 1 + 11
// = 162 < 300); TID1 = max(33 + 1, 11) = 34; TID2 = max(34, 150) = 150.
TEST(FdlTiming, ParametersAt1500kWithThePr1721Gsd) {
  const std::uint32_t gsd[] = {150};
  const BusParameters p = bus_parameters(1500000, gsd, 1, 8);
  EXPECT_EQ(p.tsl, 300u);
  EXPECT_EQ(p.max_tsdr, 150u);
  EXPECT_EQ(p.tid1, 34u);
  EXPECT_EQ(p.tid2, 150u);
  EXPECT_EQ(p.max_retry, 1);
  // One Data_Exchange of 8 bytes each way (SD3, 14 characters), answered
  // at minTSDR 11: 154 + 11 + 154 + 34 = 353 bits; plus the token (33 bits)
  // and TID2 (150): 536 bits = 357.3 us at 1.5 Mbit/s.
  EXPECT_EQ(message_cycle_bits(p, 8, 8, 11), 353u);
  EXPECT_EQ(bus_cycle_bits(p, 1, 8, 8, 11), 536u);
  EXPECT_EQ(p.bits(536).count(), 357333);
}

// 12 Mbit/s with the GSD's MaxTsdr_12M = 800: TSL 1000 covers 800 + 9 + 16
// + 11 = 836; TID1 = max(33 + 16, 11) = 49; TID2 = max(49, 800) = 800.
TEST(FdlTiming, ParametersAt12MWithThePr1721Gsd) {
  const std::uint32_t gsd[] = {800};
  const BusParameters p = bus_parameters(12000000, gsd, 4, 8);
  EXPECT_EQ(p.tsl, 1000u);
  EXPECT_EQ(p.tid1, 49u);
  EXPECT_EQ(p.tid2, 800u);
  EXPECT_EQ(p.max_retry, 4);
  // A slave slower than the profile raises maxTSDR and TSL with it.
  const std::uint32_t slow[] = {1200};
  const BusParameters q = bus_parameters(12000000, slow, 1, 8);
  EXPECT_EQ(q.max_tsdr, 1200u);
  EXPECT_EQ(q.tsl, 1200u + 9 + 16 + 11);
  // TTR: the worst case cycle + a retry + a GAP request, in 256-bit steps.
  EXPECT_EQ(p.ttr % 256, 0u);
  EXPECT_GE(p.ttr, bus_cycle_bits(p, 4, 8, 8, 800) + p.tsl * 2);
}

TEST(FdlTiming, TelegramLengths) {
  EXPECT_EQ(telegram_chars(0), 6u);   // SD1
  EXPECT_EQ(telegram_chars(8), 14u);  // SD3
  EXPECT_EQ(telegram_chars(3), 12u);  // SD2: 68 LE LEr 68 DA SA FC + 3 + FCS ED
}

// The latency/scan-time histogram: percentiles within the bucket resolution.
#include <gtest/gtest.h>

#include "plc/histogram.hpp"

using plc::Histogram;

TEST(Histogram, ExactBelowOneHundredTwentyEight) {
  Histogram h;
  for (int i = 0; i < 100; ++i) h.record(i);
  EXPECT_EQ(h.min(), 0u);
  EXPECT_EQ(h.max(), 99u);
  EXPECT_EQ(h.percentile(0.5), 49u);
  EXPECT_DOUBLE_EQ(h.mean(), 49.5);
}

TEST(Histogram, PercentilesWithinThreePercent) {
  Histogram h;
  for (std::int64_t i = 1; i <= 100000; ++i) h.record(i * 1000);  // 1 us .. 100 ms
  for (double p : {0.5, 0.9, 0.99, 0.999}) {
    const double truth = p * 100000 * 1000;
    EXPECT_NEAR(double(h.percentile(p)), truth, truth * 0.03) << p;
  }
  EXPECT_EQ(h.percentile(1.0), 100000u * 1000u);
}

TEST(Histogram, BucketsAreContiguous) {
  for (std::size_t b = 1; b < Histogram::kBuckets; ++b)
    EXPECT_EQ(Histogram::bucket_low(b), Histogram::bucket_high(b - 1) + 1) << b;
  for (std::uint64_t v : {0ull, 63ull, 64ull, 1000ull, 123456789ull})
    EXPECT_LE(Histogram::bucket_low(Histogram::bucket_of(v)), v);
}

TEST(Histogram, NegativeSamplesCountAsZero) {
  Histogram h;
  h.record(-5);
  EXPECT_EQ(h.max(), 0u);
  EXPECT_EQ(h.count(), 1u);
}

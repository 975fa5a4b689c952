#include "plc/histogram.hpp"

#include <algorithm>
#include <cmath>

namespace plc {

std::uint64_t HistogramBuckets::bucket_low(std::size_t b) {
  if (b < 2 * kSub) return b;
  const std::size_t r = b - 2 * kSub;
  const int msb = static_cast<int>(r / kSub) + kSubBits + 1;
  const std::uint64_t sub = r % kSub;
  return (kSub + sub) << (msb - kSubBits);
}

std::uint64_t HistogramBuckets::bucket_high(std::size_t b) {
  if (b < 2 * kSub) return b;
  const std::size_t r = b - 2 * kSub;
  const int msb = static_cast<int>(r / kSub) + kSubBits + 1;
  return bucket_low(b) + (1ULL << (msb - kSubBits)) - 1;
}

template <template <class> class Cell>
std::uint64_t BasicHistogram<Cell>::percentile(double p) const {
  const std::uint64_t count = count_, max = max_;
  if (count == 0) return 0;
  p = std::clamp(p, 0.0, 1.0);
  const auto rank = static_cast<std::uint64_t>(std::ceil(p * double(count)));
  if (rank >= count) return max;
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < kBuckets; ++b) {
    seen += buckets_[b];
    if (seen >= std::max<std::uint64_t>(rank, 1)) {
      const std::uint64_t mid = (bucket_low(b) + bucket_high(b)) / 2;
      return std::clamp(mid, min(), max);
    }
  }
  return max;
}

template class BasicHistogram<PlainCell>;

}  // namespace plc

// A fixed-size log-linear histogram of durations in nanoseconds (HDR-style:
// 32 sub-buckets per power of two, so a percentile is within ~3 % of the
// true value), recording in O(1) without allocation: safe inside a scan.
#pragma once

#include <array>
#include <cstdint>
#include <limits>

namespace plc {

class Histogram {
 public:
  static constexpr int kSubBits = 5;
  static constexpr std::uint64_t kSub = 1ULL << kSubBits;  // 32
  static constexpr int kMaxMsb = 42;                       // ~73 minutes
  static constexpr std::size_t kBuckets = 2 * kSub + (kMaxMsb - kSubBits) * kSub;

  void record(std::int64_t ns) {
    const std::uint64_t v = ns < 0 ? 0 : static_cast<std::uint64_t>(ns);
    ++buckets_[bucket_of(v)];
    ++count_;
    sum_ += v;
    if (v < min_) min_ = v;
    if (v > max_) max_ = v;
  }
  void clear() { *this = Histogram(); }

  [[nodiscard]] std::uint64_t count() const { return count_; }
  [[nodiscard]] std::uint64_t min() const { return count_ ? min_ : 0; }
  [[nodiscard]] std::uint64_t max() const { return max_; }
  [[nodiscard]] double mean() const { return count_ ? double(sum_) / double(count_) : 0.0; }
  // The value below which a fraction p (0..1) of the samples lie (the
  // midpoint of the bucket that holds the p-quantile, clamped to [min, max]).
  [[nodiscard]] std::uint64_t percentile(double p) const;

  static std::size_t bucket_of(std::uint64_t v) {
    if (v < 2 * kSub) return static_cast<std::size_t>(v);
    const int msb = 63 - __builtin_clzll(v);
    if (msb > kMaxMsb) return kBuckets - 1;
    const int shift = msb - kSubBits;
    return static_cast<std::size_t>(2 * kSub + (msb - kSubBits - 1) * kSub + ((v >> shift) - kSub));
  }
  static std::uint64_t bucket_low(std::size_t b);
  static std::uint64_t bucket_high(std::size_t b);

 private:
  std::array<std::uint32_t, kBuckets> buckets_{};
  std::uint64_t count_ = 0, sum_ = 0;
  std::uint64_t min_ = std::numeric_limits<std::uint64_t>::max(), max_ = 0;
};

}  // namespace plc

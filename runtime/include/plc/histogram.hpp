// A fixed-size log-linear histogram of durations in nanoseconds (HDR-style:
// 32 sub-buckets per power of two, so a percentile is within ~3 % of the
// true value), recording in O(1) without allocation: safe inside a scan.
//
// `Histogram` is the plain one, owned by one thread. A task's live
// statistics use BasicHistogram<SeqLockCell> (task_stats.hpp): the same
// buckets and recording, in cells that other threads may copy while the scan
// thread records; copying it into a plain Histogram takes the snapshot.
#pragma once

#include <array>
#include <cstdint>
#include <limits>

#include "plc/seqlock.hpp"

namespace plc {

// The bucket layout, shared by every kind of histogram.
struct HistogramBuckets {
  static constexpr int kSubBits = 5;
  static constexpr std::uint64_t kSub = 1ULL << kSubBits;  // 32
  static constexpr int kMaxMsb = 42;                       // ~73 minutes
  static constexpr std::size_t kBuckets = 2 * kSub + (kMaxMsb - kSubBits) * kSub;

  static std::size_t bucket_of(std::uint64_t v) {
    if (v < 2 * kSub) return static_cast<std::size_t>(v);
    const int msb = 63 - __builtin_clzll(v);
    if (msb > kMaxMsb) return kBuckets - 1;
    const int shift = msb - kSubBits;
    return static_cast<std::size_t>(2 * kSub + (msb - kSubBits - 1) * kSub + ((v >> shift) - kSub));
  }
  static std::uint64_t bucket_low(std::size_t b);
  static std::uint64_t bucket_high(std::size_t b);
};

template <class T>
using PlainCell = T;

// Cell: how each counter is stored (PlainCell, or SeqLockCell for one that
// other threads read while its owner records).
template <template <class> class Cell>
class BasicHistogram : public HistogramBuckets {
 public:
  BasicHistogram() = default;
  // A copy from a histogram of another storage (a snapshot of a live one).
  template <template <class> class Other>
  explicit BasicHistogram(const BasicHistogram<Other>& o)
      : count_(o.count_), sum_(o.sum_), min_(o.min_), max_(o.max_) {
    for (std::size_t b = 0; b < kBuckets; ++b) buckets_[b] = o.buckets_[b];
  }

  void record(std::int64_t ns) {
    const std::uint64_t v = ns < 0 ? 0 : static_cast<std::uint64_t>(ns);
    ++buckets_[bucket_of(v)];
    ++count_;
    sum_ += v;
    if (v < min_) min_ = v;
    if (v > max_) max_ = v;
  }
  void clear() { *this = BasicHistogram(); }

  [[nodiscard]] std::uint64_t count() const { return count_; }
  [[nodiscard]] std::uint64_t min() const { return count_ ? std::uint64_t(min_) : 0; }
  [[nodiscard]] std::uint64_t max() const { return max_; }
  [[nodiscard]] double mean() const { return count_ ? double(sum_) / double(count_) : 0.0; }
  // The value below which a fraction p (0..1) of the samples lie (the
  // midpoint of the bucket that holds the p-quantile, clamped to [min, max]).
  [[nodiscard]] std::uint64_t percentile(double p) const;

 private:
  template <template <class> class>
  friend class BasicHistogram;

  std::array<Cell<std::uint32_t>, kBuckets> buckets_{};
  Cell<std::uint64_t> count_{0}, sum_{0};
  Cell<std::uint64_t> min_{std::numeric_limits<std::uint64_t>::max()}, max_{0};
};

using Histogram = BasicHistogram<PlainCell>;

}  // namespace plc

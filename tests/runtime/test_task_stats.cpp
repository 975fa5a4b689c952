// Task statistics read while the task's scan thread records them (issue 10,
// point 4): the console's `stats`, `step` and plcrun's status line read them
// from other threads. A snapshot is one consistent set: every figure in it
// from the same scans, whatever the writer is doing meanwhile.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "plc/task_stats.hpp"

using namespace plc;

namespace {

// What the writer below has recorded after scan n (scan i took i ns; an
// overrun after every 10th scan, skipping 2 releases).
void expect_consistent(const TaskStats& s) {
  const std::uint64_t n = s.scans;
  ASSERT_EQ(s.scan_ns.count(), n);
  ASSERT_EQ(s.scan_ns.min(), n ? 1u : 0u);
  ASSERT_EQ(s.scan_ns.max(), n);
  if (n) {
    ASSERT_DOUBLE_EQ(s.scan_ns.mean(), double(n + 1) / 2) << "sum and count of one state";
  }
  // The latency of a release is recorded before its scan.
  ASSERT_TRUE(s.latency_ns.count() == n || s.latency_ns.count() == n + 1) << n;
  // The overrun of scan n is recorded after it.
  ASSERT_TRUE(s.overruns == n / 10 || (n % 10 == 0 && s.overruns + 1 == n / 10)) << n;
  ASSERT_EQ(s.skipped, 2 * s.overruns);
  ASSERT_EQ(s.scan_ns.percentile(1.0), n);
}

}  // namespace

TEST(TaskStats, SnapshotWhileTheScanThreadRecordsIsOneConsistentSet) {
  constexpr std::uint64_t kScans = 300'000;
  LiveTaskStats live;
  std::atomic<bool> done{false};
  std::thread scan_thread([&] {
    for (std::uint64_t i = 1; i <= kScans; ++i) {
      live.record_latency(std::int64_t(i));
      live.record_scan(std::int64_t(i));
      if (i % 10 == 0) live.record_overrun(2);
    }
    done.store(true);
  });
  std::uint64_t snapshots = 0, mid_run = 0;
  for (int k = 0; k < 1'000'000 && !done.load(); ++k) {  // bounded: ends with the writer
    const TaskStats s = live.snapshot();
    expect_consistent(s);
    if (HasFatalFailure()) break;
    ++snapshots;
    mid_run += s.scans > 0 && s.scans < kScans;
  }
  scan_thread.join();
  const TaskStats end = live.snapshot();
  expect_consistent(end);
  EXPECT_EQ(end.scans, kScans);
  EXPECT_EQ(end.overruns, kScans / 10);
  EXPECT_EQ(end.paused_releases, 0u);
  std::printf("%llu snapshots, %llu of them while the writer ran\n",
              static_cast<unsigned long long>(snapshots), static_cast<unsigned long long>(mid_run));
}

// Virtual time times one scan in 16 (record_scan) and only counts the
// others (count_scan), which changes the scan count alone, outside the
// write bracket: a snapshot still holds the count and the timed scans of
// one state. Scan i (from 1) is timed iff i % 16 == 1 and took i ns.
TEST(TaskStats, UntimedCountsNeedNoBracket) {
  constexpr std::uint64_t kScans = 400'000;
  LiveTaskStats live;
  std::atomic<bool> done{false};
  std::thread scan_thread([&] {
    for (std::uint64_t i = 1; i <= kScans; ++i) {
      if (i % 16 == 1)
        live.record_scan(std::int64_t(i));
      else
        live.count_scan();
    }
    done.store(true);
  });
  std::uint64_t mid_run = 0;
  for (int k = 0; k < 1'000'000 && !done.load(); ++k) {
    const TaskStats s = live.snapshot();
    const std::uint64_t n = s.scans, timed = (n + 15) / 16;
    ASSERT_EQ(s.scan_ns.count(), timed) << n;
    if (timed) {
      ASSERT_EQ(s.scan_ns.max(), 16 * (timed - 1) + 1) << n;
    }
    mid_run += n > 0 && n < kScans;
  }
  scan_thread.join();
  const TaskStats end = live.snapshot();
  EXPECT_EQ(end.scans, kScans);
  EXPECT_EQ(end.scan_ns.count(), (kScans + 15) / 16);
  std::printf("%llu snapshots while the writer ran\n", static_cast<unsigned long long>(mid_run));
}

TEST(TaskStats, TheStopReasonIsPublishedWhole) {
  LiveTaskStats live;
  EXPECT_FALSE(live.watchdog_tripped());
  EXPECT_TRUE(live.snapshot().stop_reason.empty());
  live.set_stopped(true, "watchdog: scan running for 3100 us, limit 3000 us");
  live.set_stopped(false, "a second stop changes nothing");
  const TaskStats s = live.snapshot();
  EXPECT_TRUE(s.watchdog_tripped);
  EXPECT_FALSE(s.faulted);
  EXPECT_EQ(s.stop_reason, "watchdog: scan running for 3100 us, limit 3000 us");
  EXPECT_TRUE(live.watchdog_tripped());
}

TEST(TaskStats, PausedReleasesAreCounted) {
  LiveTaskStats live;
  live.record_paused_release();
  live.record_paused_release();
  EXPECT_EQ(live.snapshot().paused_releases, 2u);
  EXPECT_EQ(live.scans(), 0u);
}

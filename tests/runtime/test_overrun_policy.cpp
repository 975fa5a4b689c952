// The real-time overrun policy (runtime.hpp, release_schedule.hpp): skip
// missed releases, never run them back to back, stay on the grid.
#include <gtest/gtest.h>

#include "plc/release_schedule.hpp"

using plc::next_release;

TEST(OverrunPolicy, OnTimeScanTakesTheNextRelease) {
  const auto n = next_release(5, 1000, 100, 1000 + 5 * 100 + 40);
  EXPECT_EQ(n.index, 6);
  EXPECT_FALSE(n.overrun);
  EXPECT_EQ(n.skipped, 0u);
}

TEST(OverrunPolicy, ScanEndingExactlyOnTheNextReleaseIsAnOverrun) {
  const auto n = next_release(0, 0, 100, 100);
  EXPECT_TRUE(n.overrun);
  EXPECT_EQ(n.index, 2);
  EXPECT_EQ(n.skipped, 1u);
}

TEST(OverrunPolicy, LongScanSkipsEveryPastReleaseAndStaysOnTheGrid) {
  // Release 3 at t=300 ran until t=651: releases 4, 5 and 6 are in the past.
  const auto n = next_release(3, 0, 100, 651);
  EXPECT_TRUE(n.overrun);
  EXPECT_EQ(n.index, 7);  // t=700, the first release after the scan ended
  EXPECT_EQ(n.skipped, 3u);
}

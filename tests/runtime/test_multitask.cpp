// Multi-task scheduling in virtual time: a 1 ms and a 10 ms task release
// exactly as configured over 10,000 base periods (issue 2 acceptance), in
// priority order within a tick.
#include <gtest/gtest.h>

#include "test_helpers.hpp"
#include "test_programs.hpp"

using namespace std::chrono_literals;

TEST(MultiTask, OneAndTenMillisecondTasksReleaseExactlyOverTenThousandBasePeriods) {
  auto rt = plctest::make_runtime(R"(
tasks:
  - {name: slow, period: 10ms, priority: 1, programs: [Slow]}
  - {name: fast, period: 1ms, priority: 0, programs: [Fast]}
programs:
  - {name: Fast, type: ReleaseLog}
  - {name: Slow, type: ReleaseLog}
)");
  EXPECT_EQ(rt->base_tick(), 1ms);
  rt->start(plc::io::ClockMode::Virtual);
  for (int i = 0; i < 10000; ++i) rt->tick();
  rt->finish();
  auto* fast = static_cast<plctest::ReleaseLog*>(rt->program("Fast"));
  auto* slow = static_cast<plctest::ReleaseLog*>(rt->program("Slow"));
  ASSERT_EQ(fast->times.size(), 10000u);
  ASSERT_EQ(slow->times.size(), 1000u);
  for (std::size_t k = 0; k < fast->times.size(); ++k) {
    ASSERT_EQ(fast->times[k], std::int64_t(k) * 1'000'000) << k;
    ASSERT_EQ(fast->cycles[k], k);
  }
  for (std::size_t k = 0; k < slow->times.size(); ++k) {
    ASSERT_EQ(slow->times[k], std::int64_t(k) * 10'000'000) << k;
    // Same tick: the fast task (priority 0) runs before the slow one.
    ASSERT_LT(fast->order[k * 10], slow->order[k]) << k;
  }
  EXPECT_EQ(rt->task("fast")->stats.scans(), 10000u);
  EXPECT_EQ(rt->task("slow")->stats.scans(), 1000u);
  EXPECT_EQ(rt->task("fast")->stats.snapshot().overruns, 0u);
}

TEST(MultiTask, NonHarmonicPeriodsUseTheirGreatestCommonDivisor) {
  auto rt = plctest::make_runtime(R"(
tasks:
  - {name: a, period: 4ms, programs: [A]}
  - {name: b, period: 6ms, programs: [B]}
programs:
  - {name: A, type: ReleaseLog}
  - {name: B, type: ReleaseLog}
)");
  EXPECT_EQ(rt->base_tick(), 2ms);
  rt->run(plc::io::ClockMode::Virtual, 120ms);
  auto* a = static_cast<plctest::ReleaseLog*>(rt->program("A"));
  auto* b = static_cast<plctest::ReleaseLog*>(rt->program("B"));
  EXPECT_EQ(a->times.size(), 30u);
  EXPECT_EQ(b->times.size(), 20u);
  EXPECT_EQ(b->times.back(), 114'000'000);
}

TEST(MultiTask, EqualPriorityRunsInConfigOrder) {
  auto rt = plctest::make_runtime(R"(
tasks:
  - {name: first, period: 1ms, priority: 3, programs: [P1]}
  - {name: second, period: 1ms, priority: 3, programs: [P2]}
programs:
  - {name: P1, type: ReleaseLog}
  - {name: P2, type: ReleaseLog}
)");
  rt->run(plc::io::ClockMode::Virtual, 5ms);
  auto* p1 = static_cast<plctest::ReleaseLog*>(rt->program("P1"));
  auto* p2 = static_cast<plctest::ReleaseLog*>(rt->program("P2"));
  for (std::size_t k = 0; k < 5; ++k) EXPECT_LT(p1->order[k], p2->order[k]);
}

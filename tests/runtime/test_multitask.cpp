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

// Issue 10 point 8: a cell with empty image areas runs (each scan copies the
// global image into the task's, area by area).
TEST(MultiTask, RunsWithEmptyImageAreas) {
  auto rt = plctest::make_runtime(R"(
image: {inputs: 0, outputs: 0, memory: 0}
tasks: [{name: a, period: 1ms, programs: [A]}]
programs: [{name: A, type: ReleaseLog}]
)");
  rt->run(plc::io::ClockMode::Virtual, 10ms);
  EXPECT_EQ(static_cast<plctest::ReleaseLog*>(rt->program("A"))->times.size(), 10u);
}

// Issue 10 point 8: devices step at every base tick (Runtime::
// kMaxTicksPerRelease says why), so periods whose greatest common divisor is
// tiny against the fastest period (1h and 1h1us: 3.6e9 device steps per
// scan) used to hang the virtual clock. Such a cell is refused when the
// virtual clock starts, with the config position of the period that causes
// it; 1000 steps per release is still accepted.
TEST(MultiTask, VirtualClockRefusesPeriodsWithoutAUsefulCommonTick) {
  auto rt = plctest::make_runtime(R"(
tasks:
  - {name: a, period: 1h, programs: [A]}
  - {name: b, period: 1h1us, programs: [B]}
programs:
  - {name: A, type: ReleaseLog}
  - {name: B, type: ReleaseLog}
)");
  ASSERT_TRUE(rt->virtual_clock_error());
  EXPECT_EQ(rt->virtual_clock_error()->mark.line, 4);
  EXPECT_NE(rt->virtual_clock_error()->message.find("3600000000 steps"), std::string::npos)
      << rt->virtual_clock_error()->message;
  EXPECT_THROW(rt->start(plc::io::ClockMode::Virtual), plc::ConfigError);
  EXPECT_EQ(rt->task("a")->stats.scans(), 0u);
}

TEST(MultiTask, VirtualClockTakesAtMostAThousandTicksPerRelease) {
  auto cell = [](const std::string& pa, const std::string& pb) {
    return plctest::make_runtime("tasks:\n  - {name: a, period: " + pa +
                                 ", programs: [A]}\n  - {name: b, period: " + pb +
                                 ", programs: [B]}\nprograms:\n  - {name: A, type: ReleaseLog}\n"
                                 "  - {name: B, type: ReleaseLog}\n");
  };
  EXPECT_TRUE(cell("1001us", "2ms")->virtual_clock_error());  // 1us tick, 1001 per release
  EXPECT_TRUE(cell("2ms", "1999us")->virtual_clock_error());  // 1us tick, 1999 per release
  EXPECT_FALSE(cell("1ms", "2ms")->virtual_clock_error());    // 1 per release
  EXPECT_FALSE(cell("2ms", "3ms")->virtual_clock_error());    // 1ms tick, 2 per release
  auto rt = cell("1ms", "1001us");                            // 1us tick, exactly 1000
  ASSERT_FALSE(rt->virtual_clock_error());
  rt->run(plc::io::ClockMode::Virtual, 1001ms);
  EXPECT_EQ(static_cast<plctest::ReleaseLog*>(rt->program("A"))->times.size(), 1001u);
  EXPECT_EQ(static_cast<plctest::ReleaseLog*>(rt->program("B"))->times.size(), 1000u);
}

// Online change in real time: the tasks run on their own threads while the
// change is prepared and committed from another; each task switches at its
// own scan boundary, and the old library goes only after both have.
#include <chrono>
#include <thread>

#include "online_fixture.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/online_change.hpp"

namespace plc::test {
namespace {

bool has(const std::string& out, const std::string& what) {
  return out.find(what) != std::string::npos;
}

TEST(OnlineChangeRealTime, TasksSwitchWhileRunning) {
  CellFolder folder;
  folder.install(PLC_TEST_FILLER_V1);
  Runtime rt(folder.config());
  std::thread runner([&] { rt.run(io::ClockMode::RealTime, std::chrono::seconds(30)); });
  // Both tasks have scanned (bounded: 10 s).
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while ((rt.tasks()[0]->stats.snapshot().scans < 5 || rt.tasks()[1]->stats.snapshot().scans < 2) &&
         std::chrono::steady_clock::now() < limit)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));

  folder.install(PLC_TEST_FILLER_V2);
  {
    OnlineChange change(rt);
    const ChangeReport report = change.prepare("");
    ASSERT_EQ(report.refused, "");
    change.commit();
    while (!change.switched() &&
           std::chrono::steady_clock::now() < limit + std::chrono::seconds(10))
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_TRUE(change.switched());
    change.finish();
  }
  const auto scans = rt.tasks()[0]->stats.snapshot().scans;
  while (rt.tasks()[0]->stats.snapshot().scans < scans + 5 &&
         std::chrono::steady_clock::now() < limit + std::chrono::seconds(20))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  rt.request_stop();
  runner.join();
  EXPECT_EQ(value(rt, "Main.build"), "2");
  EXPECT_EQ(value(rt, "Other.build"), "2");
  EXPECT_EQ(value(rt, "Main.alarms"), "7");
  for (const auto& t : rt.tasks()) EXPECT_EQ(t->stats.snapshot().stop_reason, "") << t->name;
}

// Issue 21 follow-up, point 2: a change that only some tasks took before
// it was withdrawn (the debugger's reload timing out on a stuck task). The
// fast task switched; the slow one, held at its release, did not. The
// change object goes: the fast task must go on running the new build (its
// programs and library kept by the runtime), the slow one the old. Before,
// ~OnlineChange destroyed the new programs and unloaded their library
// under the fast task (a crash; ASan: heap-use-after-free).
TEST(OnlineChangeRealTime, PartialSwitchKeepsTheNewBuildForTheTasksThatSwitched) {
  CellFolder folder;
  folder.install(PLC_TEST_FILLER_V1);
  Runtime rt(folder.config());
  TaskRuntime& fast = *rt.tasks()[0];
  TaskRuntime& slow = *rt.tasks()[1];
  std::thread runner([&] { rt.run(io::ClockMode::RealTime, std::chrono::seconds(60)); });
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  auto wait_for = [&](auto&& done) {
    while (!done() && std::chrono::steady_clock::now() < limit)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return done();
  };
  ASSERT_TRUE(wait_for([&] { return slow.stats.snapshot().scans >= 2; }));
  // Held at their releases; only the fast task may scan.
  rt.set_paused(true);
  ASSERT_TRUE(rt.wait_until_idle(std::chrono::seconds(10)));
  folder.install(PLC_TEST_FILLER_V2);
  {
    OnlineChange change(rt);
    ASSERT_EQ(change.prepare("").refused, "");
    change.commit();
    rt.allow_scans(fast, 3);
    ASSERT_TRUE(wait_for([&] { return change.switched(fast.order); }));
    EXPECT_FALSE(change.switched(slow.order));
    change.withdraw();  // the timeout: the slow task keeps the old build
    EXPECT_FALSE(change.switched());
  }  // the change object goes, as reload's does
  const auto fast_scans = fast.stats.snapshot().scans;
  const auto slow_scans = slow.stats.snapshot().scans;
  rt.set_paused(false);
  ASSERT_TRUE(wait_for([&] {
    return fast.stats.snapshot().scans >= fast_scans + 20 &&
           slow.stats.snapshot().scans >= slow_scans + 4;
  }));
  // Held again: the registry shows what each task runs.
  rt.set_paused(true);
  ASSERT_TRUE(rt.wait_until_idle(std::chrono::seconds(10)));
  EXPECT_EQ(value(rt, "Main.build"), "2");
  EXPECT_EQ(value(rt, "Main.alarms"), "7");
  EXPECT_EQ(value(rt, "Other.build"), "1");
  EXPECT_EQ(value(rt, "Other.note"), "42");

  // A later change completes it: both tasks on the newest build, and the
  // old programs the partial change kept go before their library (the
  // runtime's destruction below would otherwise run their destructors in
  // an unloaded library).
  folder.install(PLC_TEST_FILLER_V1);
  {
    OnlineChange again(rt);
    ASSERT_EQ(again.prepare("").refused, "");
    again.commit();
    rt.allow_scans(fast, 3);
    rt.allow_scans(slow, 3);
    ASSERT_TRUE(wait_for([&] { return again.switched(); }));
    again.finish();
  }
  rt.set_paused(false);
  rt.request_stop();
  runner.join();
  EXPECT_EQ(value(rt, "Main.note"), "42");
  EXPECT_EQ(value(rt, "Other.note"), "42");
  for (const auto& t : rt.tasks()) EXPECT_EQ(t->stats.snapshot().stop_reason, "") << t->name;
}

// The debugger's `reload` while the logic runs in real time, with a force,
// a conditional breakpoint and a trace set up: each task takes them over at
// its own switch point (reload.cpp); the force on a variable the new build
// lacks is dropped and listed.
TEST(OnlineChangeRealTime, ForcesConditionsAndTraceCarryAcrossTheSwitch) {
  CellFolder folder;
  folder.install(PLC_TEST_FILLER_V1);
  static CellConfig cfg;
  cfg = folder.config();
  debug::Debugger::Options o;
  o.mode = io::ClockMode::RealTime;
  o.span = std::chrono::seconds(60);
  debug::Debugger d([] { return std::make_unique<Runtime>(cfg); }, o);
  auto scans = [&] { return d.runtime().tasks()[0]->stats.snapshot().scans; };
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  auto wait_scans = [&](std::uint64_t n) {  // bounded: 20 s in all
    while (scans() < n && std::chrono::steady_clock::now() < limit)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
  };
  wait_scans(3);
  EXPECT_TRUE(has(d.execute("force Main.weight 3.5"), "3.5")) << d.execute("forces");
  d.execute("force Main.note 5");
  d.execute("break Main.step = 99");
  d.execute("trace add Main.weight");
  wait_scans(scans() + 3);

  folder.install(PLC_TEST_FILLER_V2);
  const std::string out = d.execute("reload");
  EXPECT_TRUE(has(out, "switched")) << out;
  EXPECT_TRUE(has(out, "force on Main.note dropped")) << out;
  wait_scans(scans() + 5);
  // The force holds in the new build: the program adds flow each scan, the
  // force puts 3.5 back after the programs.
  EXPECT_TRUE(has(d.execute("print Main.weight"), "= 3.5")) << d.execute("print Main.weight");
  EXPECT_TRUE(has(d.execute("print Main.build"), "2"));
  const std::string forces = d.execute("forces");
  EXPECT_TRUE(has(forces, "Main.weight")) << forces;
  EXPECT_FALSE(has(forces, "Main.note")) << forces;
  EXPECT_TRUE(has(d.execute("trace"), "Main.weight")) << d.execute("trace");
  EXPECT_TRUE(has(d.execute("break"), "Main.step = 99")) << d.execute("break");
  d.execute("quit");
}

}  // namespace
}  // namespace plc::test

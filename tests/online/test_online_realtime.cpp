// Online change in real time: the tasks run on their own threads while the
// change is prepared and committed from another; each task switches at its
// own scan boundary, and the old library goes only after both have.
#include <chrono>
#include <thread>

#include "online_fixture.hpp"
#include "plc/online_change.hpp"

namespace plc::test {
namespace {

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
    while (!change.switched() && std::chrono::steady_clock::now() < limit + std::chrono::seconds(10))
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

}  // namespace
}  // namespace plc::test

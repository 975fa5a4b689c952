// What the console and other threads read while real-time task threads run
// (issue 10, point 4). Each of these raced before, and a ThreadSanitizer
// build reports that (scripts/test-tsan runs them); the checks on the values
// fail without TSan too when the race strikes.
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <thread>

#include "debugger_deadline.hpp"
#include "plc/debug/debugger.hpp"
#include "test_helpers.hpp"
#include "test_programs.hpp"

using namespace plc;

namespace {

bool has(const std::string& out, const std::string& what) {
  return out.find(what) != std::string::npos;
}

std::unique_ptr<debug::Debugger> realtime_debugger(const std::string& yaml) {
  const CellConfig cfg = parse_cell_config(yaml, "rt_sync.yaml");
  debug::Debugger::Options o;
  o.mode = io::ClockMode::RealTime;
  o.span = std::chrono::seconds(60);
  return std::make_unique<debug::Debugger>([cfg] { return std::make_unique<Runtime>(cfg); }, o);
}

// "NAME = V" in the output of `print`; -1 when missing.
long value_of(const std::string& out, const std::string& name) {
  const std::size_t p = out.find(name + " = ");
  if (p == std::string::npos) return -1;
  return std::strtol(out.c_str() + p + name.size() + 3, nullptr, 10);
}

// Task a (1 ms) stops at a breakpoint while task b (10 ms, 5 ms of work per
// scan between setting `first` and `second`) is usually in the middle of a
// scan. What the console prints after the stop must come from settled
// tasks: b's pair equal, and the located %QX8.0 read from the global image.
// No watchdogs in these cells: b spends half its time inside a scan, so a
// loaded machine that stalls the process for 100 ms would trip b's (10 x
// 10 ms, wall time), and the tests here are not about it.
const char* kTwoTasks = R"(
tasks:
  - {name: a, period: 1ms, watchdog: 0, programs: [A]}
  - {name: b, period: 10ms, watchdog: 0, programs: [B, W]}
programs:
  - {name: A, type: PairWriter, init: {work_us: 100}}
  - {name: B, type: PairWriter, init: {work_us: 5000}}
  - {name: W, type: BitWriter}
)";

// Task a (1 ms) and task b (2 ms): b counts into the located %QD0 (its
// L.to_dev), so the global image changes at every merge of b.
const char* kCounterTasks = R"(
tasks:
  - {name: a, period: 1ms, watchdog: 0, programs: [A]}
  - {name: b, period: 2ms, watchdog: 0, programs: [L]}
programs:
  - {name: A, type: PairWriter, init: {work_us: 50}}
  - {name: L, type: LoopCounter}
)";

}  // namespace

// In real time a condition or a trace row is evaluated on one task's scan
// thread right after its scan (one_task.hpp): a variable of another task is
// being written by that task's thread meanwhile, so mixing two tasks'
// variables is refused when the command is given, with the reason.
// Addresses (the global image) go with either task.
TEST(RealTimeSync, ConditionsAndTracesMixingTwoTasksAreRefusedWithTheReason) {
  auto dbg = realtime_debugger(kCounterTasks);
  debug::Debugger& d = *dbg;
  const char* why =
      "in real time the variables must belong to one task: A.first belongs to "
      "task 'a', L.count to task 'b'";
  std::string out = d.execute("break A.first > 5 AND L.count > 5");
  EXPECT_TRUE(has(out, std::string("break: ") + why)) << out;
  out = d.execute("run until A.first > 3 OR L.count > 3");
  EXPECT_TRUE(has(out, std::string("run until: ") + why)) << out;
  out = d.execute("break L.to_dev > 5 AND A.first > 5");
  EXPECT_TRUE(has(out, "L.to_dev belongs to task 'b', A.first to task 'a'")) << out;
  EXPECT_TRUE(has(d.execute("breaks"), "no breakpoints"));
  // One task plus addresses is fine.
  EXPECT_TRUE(has(d.execute("break A.first > 1000000 AND %QD0 > 0"), "breakpoint 1:"));
  EXPECT_TRUE(has(d.execute("trace add A.first %QD0"), "2 variable(s)"));
  out = d.execute("trace add L.count");
  EXPECT_TRUE(has(out, "trace add: in real time the variables must belong to one task")) << out;
  out = d.execute("trace trigger L.count > 3");
  EXPECT_TRUE(has(out, "trace trigger: in real time the variables must belong to one task")) << out;
  out = d.execute("trace status");
  EXPECT_TRUE(has(out, "2 variable(s) A.first %QD0; no trigger")) << out;
  d.execute("quit");
}

// A condition and a trace on the global image (%QD0, which task b's merges
// write under the image lock) are evaluated and sampled after the scans of
// task a too: they read the image under the image lock (TSan reports the
// race otherwise), so every row and every evaluation sees whole merges.
TEST(RealTimeSync, ConditionsAndTraceRowsReadTheGlobalImageUnderTheImageLock) {
  auto dbg = realtime_debugger(kCounterTasks);
  debug::Debugger& d = *dbg;
  const std::string csv = plctest::temp_path("rt_trace.csv");
  EXPECT_TRUE(has(d.execute("trace add A.first %QD0"), "2 variable(s)"));
  EXPECT_TRUE(has(d.execute("trace start " + csv), "running into"));
  {
    plctest::Deadline deadline(d);
    const std::string stop = d.execute("run until %QD0 >= 150");
    ASSERT_TRUE(has(stop, "condition '%QD0 >= 150' holds")) << stop;
  }
  EXPECT_TRUE(has(d.execute("trace stop"), "rows written"));
  EXPECT_GE(value_of(d.execute("print L.to_dev"), "L.to_dev"), 150);
  // The rows come from task a's scans (A.first goes up by one) and %QD0
  // only ever counts up.
  std::istringstream rows(plctest::read_file(csv));
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line, "time_ns,cycle,A.first,%QD0");
  long last_first = -1, last_q = -1, n = 0;
  while (std::getline(rows, line)) {
    long t = 0, c = 0, first = 0, q = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%ld,%ld,%ld,%ld", &t, &c, &first, &q), 4) << line;
    if (last_first >= 0) {
      EXPECT_EQ(first, last_first + 1) << line;
    }
    EXPECT_GE(q, last_q) << line;
    last_first = first;
    last_q = q;
    ++n;
  }
  EXPECT_GT(n, 0);
  std::remove(csv.c_str());
  d.execute("quit");
}

// `continue for D` in real time runs D of real time, then pauses (as in
// virtual time); Ctrl-C (interrupt) ends it early. It used to return at once
// and leave the tasks running.
TEST(RealTimeSync, ContinueForRunsThatLongThenPauses) {
  auto dbg = realtime_debugger(kCounterTasks);
  debug::Debugger& d = *dbg;
  d.execute("pause");
  const TaskRuntime& a = *d.runtime().task("a");
  const std::uint64_t before = a.stats.scans();
  // Long enough that a stall of the whole machine (100 ms) cannot take all
  // of it: the tasks must have scanned in it.
  const std::string out = d.execute("continue for 500ms");
  EXPECT_TRUE(has(out, "stopped: ran for T#500ms")) << out;
  EXPECT_TRUE(d.runtime().paused()) << "the session pauses at the end of the span";
  EXPECT_EQ(d.prompt(), "[realtime paused] > ");
  const std::uint64_t after = a.stats.scans();
  EXPECT_GT(after, before) << "the tasks ran";
  // Paused and settled: a step lets exactly one more scan of a through.
  EXPECT_TRUE(has(d.execute("step task a 1"), "stepped 1 scan(s) of task 'a'"));
  EXPECT_EQ(a.stats.scans(), after + 1);
  // A long span ends early on Ctrl-C, paused too.
  std::thread ctrl_c([&] {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (a.stats.scans() < after + 20 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::yield();
    d.interrupt();
  });
  const std::string longer = d.execute("continue for 1h");
  ctrl_c.join();
  EXPECT_TRUE(has(longer, "stopped: interrupted")) << longer;
  EXPECT_TRUE(d.runtime().paused());
  d.execute("quit");
}

// A stop (breakpoint, pause, step) waits until no task is inside a scan, so
// reading the variables afterwards never sees half a scan.
TEST(RealTimeSync, AStopWaitsForTheScansInFlightBeforeValuesAreRead) {
  auto dbg = realtime_debugger(kTwoTasks);
  debug::Debugger& d = *dbg;
  long last_a = 0;
  for (int i = 1; i <= 12; ++i) {
    const std::string stop = d.execute("run until A.first >= " + std::to_string(last_a + 3));
    ASSERT_TRUE(has(stop, "holds")) << stop;
    const std::string out = d.execute("print A.first A.second B.first B.second W.mine %QX8.0");
    EXPECT_EQ(value_of(out, "B.first"), value_of(out, "B.second")) << "half a scan of b:\n" << out;
    EXPECT_EQ(value_of(out, "A.first"), value_of(out, "A.second")) << out;
    EXPECT_TRUE(has(out, "%QX8.0 = ")) << out;
    last_a = value_of(out, "A.first");
    // Paused: nothing scans, so a second look shows the same.
    EXPECT_EQ(d.execute("print A.first B.first"), d.execute("print A.first B.first"));
    if (i % 3 == 0) {
      // `pause` from running settles the same way.
      EXPECT_TRUE(has(d.execute("continue"), "running"));
      EXPECT_TRUE(has(d.execute("pause"), "paused"));
      const std::string p = d.execute("print B.first B.second A.first");
      EXPECT_EQ(value_of(p, "B.first"), value_of(p, "B.second")) << p;
      last_a = value_of(p, "A.first");
    }
  }
  d.execute("quit");
}

// `step N` counts only the scans it lets through: a scan that was in flight
// when it paused is not one of them.
TEST(RealTimeSync, StepRunsExactlyTheScansItAllows) {
  auto dbg = realtime_debugger(kTwoTasks);
  debug::Debugger& d = *dbg;
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(has(d.execute("continue"), "running"));
    const std::string before = d.execute("step task b 1");
    ASSERT_TRUE(has(before, "stepped 1 scan(s) of task 'b'")) << before;
    const long b0 = value_of(d.execute("print B.first"), "B.first");
    const std::string out = d.execute("step task b 2");
    EXPECT_TRUE(has(out, "stepped 2 scan(s) of task 'b'")) << out;
    const std::string p = d.execute("print B.first B.second");
    EXPECT_EQ(value_of(p, "B.first"), b0 + 2) << p;
    EXPECT_EQ(value_of(p, "B.second"), b0 + 2) << p;
  }
  d.execute("quit");
}

// `stats` while the tasks run: each task's figures are one snapshot (and,
// for TSan, read without racing the scan threads that record them).
TEST(RealTimeSync, StatsWhileRunningAreOneSnapshotPerTask) {
  auto dbg = realtime_debugger(kTwoTasks);
  debug::Debugger& d = *dbg;
  EXPECT_TRUE(has(d.execute("continue"), "running"));
  unsigned long long last = 0;
  for (int i = 0; i < 50; ++i) {
    const std::string out = d.execute("stats");
    unsigned long long scans = 0, overruns = 0, skipped = 0;
    double mn = 0, avg = 0, p99 = 0, mx = 0;
    ASSERT_EQ(std::sscanf(out.c_str(),
                          "task a: period T#1ms, %llu scans, %llu overruns (%llu skipped)\n"
                          "  scan time us: min %lf avg %lf p99 %lf max %lf",
                          &scans, &overruns, &skipped, &mn, &avg, &p99, &mx),
              7)
        << out;
    EXPECT_GE(scans, last);
    last = scans;
    if (scans > 0) {
      EXPECT_LE(mn, avg) << out;
      EXPECT_LE(avg, mx) << out;
      EXPECT_LE(p99, mx) << out;
    }
    // Give the tasks time to scan between two looks: a print waits for the
    // end of a scan of task a.
    d.execute("print A.first");
  }
  EXPECT_GT(last, 0u);
  d.execute("quit");
}

// The watchdog thread stops a real-time task and writes why while another
// thread reads the task's statistics: the reader sees no reason or the
// whole one, never one being written.
TEST(RealTimeSync, AWatchdogStopIsSeenWholeByAReaderOfTheStatistics) {
  // The other task keeps the run going until the spinning scan has ended,
  // so its thread is joined, not left behind.
  auto rt = plctest::make_runtime(R"(
tasks:
  - {name: fast, period: 1ms, watchdog: 3, programs: [Spin]}
  - {name: other, period: 10ms, programs: [Loop]}
programs:
  - {name: Spin, type: Spinner, init: {spin: TRUE, spin_us: 50000}}
  - {name: Loop, type: LoopCounter}
)");
  const TaskRuntime& t = *rt->task("fast");
  std::thread runner([&] { rt->run(io::ClockMode::RealTime, std::chrono::milliseconds(400)); });
  TaskStats seen;
  for (int i = 0; i < 2'000'000 && seen.stop_reason.empty(); ++i) {  // ends with the trip
    seen = t.stats.snapshot();
    if (seen.stop_reason.empty()) std::this_thread::yield();
  }
  runner.join();
  EXPECT_TRUE(seen.watchdog_tripped);
  EXPECT_FALSE(seen.faulted);
  EXPECT_EQ(seen.stop_reason.rfind("watchdog: scan running for ", 0), 0u) << seen.stop_reason;
  EXPECT_EQ(t.stats.snapshot().stop_reason, seen.stop_reason) << "written once";
}

// A real-time plcrun --commands session on the demo cell with the commands
// that read while the tasks run or right after they stop (in a TSan build
// the child exits non-zero on any race, and the test fails). Without the
// watchdogs: a scan stalled past 10 ms on a loaded machine would stop the
// task, and the forces printed below would never be applied by a scan.
TEST(RealTimeSync, PlcrunCommandsSessionInRealTime) {
  const std::string demo = plctest::demo_without_watchdogs("rt_session_demo.yaml");
  ASSERT_FALSE(demo.empty()) << "programs/demo/cell.yaml changed";
  const std::string cmds = plctest::write_temp("rt_session.txt", R"(stats
step 5
print Tank.level Tank.valve %QW0 %IW0 Tank.enable Supervisor.enable
watch Tank.step Tank.valve %QW0 Supervisor.batches_seen
step task slow 2
continue
print Tank.level Tank.valve %QW0 %IW0 %MX0.0 Supervisor.enable
stats
status
pause
print Tank.level Tank.valve %QW0 %IW0 %MX0.0
stats
write Tank.low_level 3000
write %QW0 100
force Tank.high_level 9000
force %MX0.0 TRUE
forces
step 3
print Tank.high_level %MX0.0
continue
print Tank.high_level %MX0.0 %QW0
unforce Tank.high_level restore
unforce all
break Tank.valve > 0
continue
delete all
run until Supervisor.enable
stats
continue
print Tank.level Tank.valve %QW0 %IW0
trace status
pause
quit
)");
  const auto r =
      plctest::run_command(plctest::plcrun_path() + " " + demo + " --realtime --commands " + cmds);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* expect :
       {"stepped 5 scan(s) of each task", "stepped 2 scan(s) of task 'slow'", "paused: the logic",
        "Tank.high_level = 9000  (INT, forced)", "restoring 22000",
        "condition 'Supervisor.enable' holds", "task slow: period T#10ms"})
    EXPECT_TRUE(has(r.output, expect)) << "missing: " << expect << "\n" << r.output;
  EXPECT_FALSE(has(r.output, "ThreadSanitizer")) << r.output;
  EXPECT_FALSE(has(r.output, "<no value")) << r.output;
  std::remove(cmds.c_str());
}

// The debugger's command layer in virtual time (issue 6): every command,
// driven through Debugger::execute as the console and --commands do.
#include <gtest/gtest.h>

#include <deque>

#include "../../programs/demo/tank_cycle.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/io/sim_plugin.hpp"
#include "test_helpers.hpp"

using namespace plc;
using plc::debug::Debugger;

namespace {

std::string demo_path() { return plctest::source_path("programs/demo/cell.yaml"); }

std::unique_ptr<Debugger> demo_debugger(std::string replay = "", CellConfig* cfg_out = nullptr) {
  static CellConfig cfg;
  cfg = load_cell_config(demo_path());
  if (cfg_out) *cfg_out = cfg;
  Debugger::Options o;
  o.replay_file = std::move(replay);
  o.span = std::chrono::minutes(10);
  return std::make_unique<Debugger>([] { return std::make_unique<Runtime>(cfg); }, o);
}

bool has(const std::string& out, const std::string& what) {
  return out.find(what) != std::string::npos;
}

// Freeze points read their commands from `script` and print into `printed`.
void scripted_io(Debugger& d, std::deque<std::string>& script, std::string& printed) {
  d.set_io(
      [&script](const std::string&) -> std::optional<std::string> {
        if (script.empty()) return std::nullopt;
        auto l = script.front();
        script.pop_front();
        return l;
      },
      [&printed](const std::string& s) { printed += s; });
}

// Every variable's value in IEC notation: the whole visible state.
std::string snapshot(Runtime& rt) {
  std::string s;
  for (const VarInfo& v : rt.vars().all()) s += v.path + "=" + VarRegistry::format(v) + "\n";
  return s;
}

// The demo's tank program with a changed valve law: same variables, same
// layout, different behaviour (what a code fix replayed against a bench
// recording looks like).
class TankCycleHalfValve : public demo::TankCycle {
 public:
  void cycle(const ScanContext& ctx) override {
    demo::TankCycle::cycle(ctx);
    if (valve > 0) valve = INT(valve / 2);
  }
};
PLC_REGISTER_PROGRAM(TankCycleHalfValve)

}  // namespace

TEST(Debugger, StartsPausedBeforeTheFirstScanAndStepsScanByScan) {
  auto d = demo_debugger();
  EXPECT_EQ(d->scan_count(), 0u);
  EXPECT_TRUE(has(d->prompt(), "[scan 0 "));
  std::string out = d->execute("step");
  EXPECT_TRUE(has(out, "stepped 1 scan(s)")) << out;
  EXPECT_EQ(d->scan_count(), 1u);
  out = d->execute("step 9");
  EXPECT_EQ(d->scan_count(), 10u);
  // Scans 1..10: t=0 runs fast then slow (2 scans), then fast alone each ms.
  EXPECT_TRUE(has(out, "task 'fast' at t=0.008000s")) << out;
  out = d->execute("step task slow 1");
  EXPECT_TRUE(has(out, "of task 'slow'")) << out;
  EXPECT_EQ(d->runtime().task("slow")->stats.scans(), 2u);
  EXPECT_EQ(d->scan_count(), 13u) << "fast at 9 and 10 ms, then slow at 10 ms";
  EXPECT_TRUE(has(d->execute("step 0"), "not a positive count"));
  EXPECT_TRUE(has(d->execute("step task nope"), "unknown task 'nope'"));
}

TEST(Debugger, PrintShowsIecNotationForVariablesFbInternalsAndAddresses) {
  auto d = demo_debugger();
  d->execute("step 700");
  const std::string out = d->execute(
      "print Tank.hold_time Supervisor.enable Tank.tank_status %QX2.0 Tank.hold.running_");
  EXPECT_TRUE(has(out, "Tank.hold_time = T#2s  (TIME)")) << out;
  EXPECT_TRUE(has(out, "Supervisor.enable = TRUE  (BOOL %MX0.0)")) << out;
  EXPECT_TRUE(has(out, "Tank.tank_status = 16#0001  (WORD %IW2)")) << out;
  EXPECT_TRUE(has(out, "%QX2.0 = TRUE")) << out;
  EXPECT_TRUE(has(out, "Tank.hold.running_ = FALSE")) << out;
  EXPECT_TRUE(has(d->execute("print Tank.nothing"), "unknown variable 'Tank.nothing'"));
  EXPECT_TRUE(has(d->execute("print %QX0.9"), "out of range 0..7"));
}

TEST(Debugger, BreakpointStopsAtTheEndOfTheScanWhereItsConditionHolds) {
  auto d = demo_debugger();
  EXPECT_TRUE(has(d->execute("break Tank.step = 3"), "breakpoint 1: Tank.step = 3"));
  std::string out = d->execute("continue");
  EXPECT_TRUE(has(out, "breakpoint 1 (Tank.step = 3) hit, 1 hit(s)")) << out;
  EXPECT_TRUE(has(d->execute("print Tank.step"), "Tank.step = 3"));
  // The same scan must not show Drain one scan earlier: go back one and look.
  const auto at = d->scan_count();
  d->execute("goto " + std::to_string(at - 1));
  EXPECT_TRUE(has(d->execute("print Tank.step"), "Tank.step = 2"));
  EXPECT_TRUE(has(d->execute("breaks"), "1: Tank.step = 3  hits 0"))
      << "hit counts restart with the cell";
  EXPECT_TRUE(has(d->execute("delete 1"), "deleted 1"));
  EXPECT_TRUE(has(d->execute("breaks"), "no breakpoints"));
  EXPECT_TRUE(has(d->execute("delete 7"), "no breakpoint 7"));
  EXPECT_TRUE(has(d->execute("break Tank.step ="), "incomplete condition"));
  EXPECT_TRUE(has(d->execute("break Tank.nope > 1"), "unknown variable 'Tank.nope'"));
}

TEST(Debugger, HitCountStopsOnEveryNthHit) {
  auto d = demo_debugger();
  d->execute("break Tank.drained.Q hits 2");  // one pulse per batch
  std::string out = d->execute("continue");
  EXPECT_TRUE(has(out, "2 hit(s)")) << out;
  EXPECT_TRUE(has(d->execute("print Tank.batches.CV"), "Tank.batches.CV = 2"))
      << "stopped on the 2nd batch";
  out = d->execute("continue");
  EXPECT_TRUE(has(out, "4 hit(s)")) << out;
}

TEST(Debugger, RunUntilAndContinueFor) {
  auto d = demo_debugger();
  std::string out = d->execute("run until Tank.level > 16#4000 AND Tank.step = 1");
  EXPECT_TRUE(has(out, "condition 'Tank.level > 16#4000 AND Tank.step = 1' holds")) << out;
  EXPECT_TRUE(has(d->execute("breaks"), "no breakpoints"))
      << "run until leaves no breakpoint behind";
  const auto before = d->runtime().task("fast")->stats.scans();
  out = d->execute("continue for 250ms");
  EXPECT_TRUE(has(out, "ran for T#250ms")) << out;
  EXPECT_EQ(d->runtime().task("fast")->stats.scans() - before, 250u);
}

TEST(Debugger, WriteAppliesOnceAtTheNextScan) {
  auto d = demo_debugger();
  d->execute("step 2");
  EXPECT_TRUE(has(d->execute("write Tank.high_level 1234"), "at the start of the next scan"));
  EXPECT_TRUE(has(d->execute("print Tank.high_level"), "= 22000")) << "not before the scan";
  d->execute("step");
  EXPECT_TRUE(has(d->execute("print Tank.high_level"), "= 1234"));
  EXPECT_TRUE(has(d->execute("write Tank.high_level abc"), "not an integer"));
  EXPECT_TRUE(has(d->execute("write Tank.name 1"), "unknown variable"));
}

TEST(Debugger, ForcedInputIsWhatTheProgramSeesAndUnforceRestores) {
  auto d = demo_debugger();
  d->execute("step 20");
  // %IW0 is the tank level from the device: force it high; the program
  // sees it (goes to Hold once enabled) although the device says otherwise.
  EXPECT_TRUE(has(d->execute("force Tank.level 25000"), "every scan until unforce"));
  EXPECT_TRUE(has(d->execute("forces"), "Tank.level := 25000  (before: 0)"));
  d->execute("continue for 600ms");
  std::string out = d->execute("print Tank.level Tank.step");
  EXPECT_TRUE(has(out, "Tank.level = 25000")) << out;
  EXPECT_TRUE(has(out, "Tank.step = 2")) << out;
  EXPECT_TRUE(has(d->execute("unforce Tank.level"), "keeping the value"));
  d->execute("step 3");
  EXPECT_FALSE(has(d->execute("print Tank.level"), "25000")) << "an input follows its device again";
  EXPECT_TRUE(has(d->execute("forces"), "no forces"));
  EXPECT_TRUE(has(d->execute("unforce Tank.level"), "is not forced"));
}

TEST(Debugger, ForcedOutputReachesTheDeviceWhateverTheProgramWrites) {
  auto d = demo_debugger();
  d->execute("continue for 1s");  // filling: the program writes valve = 27648
  d->execute("force %QW0 16#0100");
  d->execute("step 3");
  auto* sim = static_cast<io::SimPlugin*>(d->runtime().plugin("sim"));
  auto out = sim->device("tank1")->outputs();
  EXPECT_EQ(out[0], 0x01);
  EXPECT_EQ(out[1], 0x00);
  const std::string p = d->execute("print Tank.valve");
  EXPECT_TRUE(has(p, "Tank.valve = 27648")) << "the program's own view" << p;
  EXPECT_TRUE(has(p, "image: 256, forced")) << p;
  d->execute("unforce %QW0");
  d->execute("step 2");
  EXPECT_EQ(out[0], 0x6C) << "27648 = 16#6C00 again";
}

TEST(Debugger, ForcedProgramVariableHoldsAtStartAndEndOfItsScan) {
  auto d = demo_debugger();
  d->execute("force Tank.step 3");  // Drain, whatever the program decides
  d->execute("continue for 2s");
  EXPECT_TRUE(has(d->execute("print Tank.step Tank.valve"), "Tank.step = 3  (INT, forced)"));
  EXPECT_TRUE(has(d->execute("unforce Tank.step restore"), "restoring 1"));
  d->execute("step");
  EXPECT_TRUE(has(d->execute("print Tank.step"), "Tank.step = 1"));
}

TEST(Debugger, WatchListIsPrintedAtEveryStop) {
  auto d = demo_debugger();
  EXPECT_TRUE(has(d->execute("watch Tank.step Tank.valve"), "Tank.step = 1"));
  EXPECT_TRUE(has(d->execute("step"), "  Tank.valve = 0"));
  d->execute("unwatch Tank.valve");
  const std::string out = d->execute("step");
  EXPECT_TRUE(has(out, "Tank.step ="));
  EXPECT_FALSE(has(out, "Tank.valve"));
  EXPECT_TRUE(has(d->execute("watch Tank.zzz"), "unknown variable"));
}

TEST(Debugger, FreezePointStopsBetweenProgramCallsAndTakesCommands) {
  auto d = demo_debugger();
  std::deque<std::string> script = {"print Tank.step", "write Tank.high_level 5", "continue"};
  std::string printed;
  scripted_io(*d, script, printed);
  EXPECT_TRUE(has(d->execute("break before Tank if Supervisor.enable"),
                  "before Tank if Supervisor.enable"));
  EXPECT_TRUE(has(d->execute("break before Nope"), "no task runs a program named 'Nope'"));
  const std::string out = d->execute("continue for 1s");
  EXPECT_TRUE(has(printed, "frozen before program 'Tank' of task 'fast'")) << printed;
  EXPECT_TRUE(has(printed, "Tank.step = 1")) << printed;
  EXPECT_TRUE(has(printed, "now, inside the scan")) << printed;
  // The write made inside the frozen scan took effect in that same scan.
  EXPECT_TRUE(has(d->execute("print Tank.high_level"), "= 5"));
  EXPECT_TRUE(has(d->execute("print Tank.step"), "= 2")) << "level >= 5 -> Hold";
  (void)out;
}

TEST(Debugger, TraceWritesCsvAndVcdWithTriggerAndPretrigger) {
  auto d = demo_debugger();
  const std::string csv = plctest::temp_path("dbg_trace.csv");
  d->execute("trace add Tank.level Tank.step %QW0");
  d->execute("trace trigger Tank.step = 3");
  d->execute("trace pre 2");
  EXPECT_TRUE(has(d->execute("trace start " + csv), "waiting for trigger"));
  d->execute("continue for 8s");
  EXPECT_TRUE(has(d->execute("trace stop"), "rows written"));
  const std::string text = plctest::read_file(csv);
  ASSERT_TRUE(has(text, "time_ns,cycle,Tank.level,Tank.step,%QW0\n")) << text.substr(0, 200);
  // Two pre-trigger rows (step 2), then the trigger row (step 3).
  std::vector<std::string> lines;
  for (std::size_t p = 0, q; (q = text.find('\n', p)) != std::string::npos; p = q + 1)
    lines.push_back(text.substr(p, q - p));
  ASSERT_GE(lines.size(), 4u);
  EXPECT_TRUE(has(lines[1], ",2,")) << lines[1];
  EXPECT_TRUE(has(lines[2], ",2,")) << lines[2];
  EXPECT_TRUE(has(lines[3], ",3,")) << lines[3];

  const std::string vcd = plctest::temp_path("dbg_trace.vcd");
  d->execute("trace trigger off");
  d->execute("trace start " + vcd);
  d->execute("step 5");
  d->execute("trace stop");
  const std::string v = plctest::read_file(vcd);
  EXPECT_TRUE(has(v, "$timescale 1ns $end")) << v;
  EXPECT_TRUE(has(v, "$scope module Tank $end")) << v;
  EXPECT_TRUE(has(v, "$var integer 16 ! level $end")) << v;
  EXPECT_TRUE(has(v, "$enddefinitions $end")) << v;
  EXPECT_TRUE(has(d->execute("trace add Tank.nope"), "unknown variable"));
  EXPECT_TRUE(has(d->execute("trace bogus"), "unknown subcommand"));
}

TEST(Debugger, GotoLandsOnTheSameStateAsRunningThere) {
  auto a = demo_debugger();
  a->execute("goto 20000");
  const std::string at20000 = snapshot(a->runtime());
  a->execute("goto 5000");  // backwards: re-runs from the start
  EXPECT_EQ(a->scan_count(), 5000u);
  const std::string back = snapshot(a->runtime());
  auto b = demo_debugger();
  b->execute("step 5000");
  EXPECT_EQ(back, snapshot(b->runtime()));
  EXPECT_NE(back, at20000);
  a->execute("goto 20000");
  EXPECT_EQ(snapshot(a->runtime()), at20000);
}

TEST(Debugger, RecordingReplaysWithIdenticalOutputsForOneHundredThousandScans) {
  const std::string rec = plctest::temp_path("dbg.rec");
  {
    auto d = demo_debugger();
    EXPECT_TRUE(has(d->execute("record " + rec), "recording"));
    d->execute("goto 100000");
    EXPECT_TRUE(has(d->execute("record stop"), "100000 scans"));
  }
  auto r = demo_debugger(rec);
  const std::string out = r->execute("continue");
  EXPECT_TRUE(has(out, "the recording has ended")) << out;
  EXPECT_TRUE(has(out, "replay 100000 scans, 0 output mismatch(es)")) << out;
  // goto in a replay re-runs the recording.
  r->execute("goto 5000");
  auto live = demo_debugger();
  live->execute("goto 5000");
  EXPECT_EQ(snapshot(r->runtime()), snapshot(live->runtime()));
}

TEST(Debugger, ReplayDetectsAProgramThatBehavesDifferently) {
  const std::string rec = plctest::temp_path("dbg_diff.rec");
  {
    auto d = demo_debugger();
    d->execute("record " + rec);
    d->execute("goto 20000");
    d->execute("record stop");
  }
  CellConfig cfg = load_cell_config(demo_path());
  cfg.programs[0].type.value = "TankCycleHalfValve";
  Debugger::Options o;
  o.replay_file = rec;
  Debugger r([&cfg] { return std::make_unique<Runtime>(cfg); }, o);
  const std::string out = r.execute("continue");
  EXPECT_FALSE(has(out, " 0 output mismatch(es)")) << out;
  EXPECT_TRUE(has(out, "first at scan")) << out;
}

TEST(Debugger, ReplayRefusesARecordingOfAnotherCell) {
  const std::string rec = plctest::temp_path("dbg_other.rec");
  {
    auto rt = plctest::make_runtime(R"(
tasks: [{name: main, period: 1ms, programs: [Loop]}]
programs: [{name: Loop, type: LoopCounter}]
)");
    debug::Recorder r(*rt, rec);
  }
  EXPECT_THROW(demo_debugger(rec), std::runtime_error);
}

TEST(Debugger, StatsStatusHelpQuitAndUnknownCommands) {
  auto d = demo_debugger();
  d->execute("step 30");
  EXPECT_TRUE(has(d->execute("stats"), "task fast: period T#1ms, 27 scans"));
  EXPECT_TRUE(has(d->execute("status"), "at scan 30"));
  EXPECT_TRUE(has(d->execute("help"), "goto SCAN"));
  EXPECT_TRUE(has(d->execute("pause"), "paused"));
  EXPECT_TRUE(has(d->execute("frobnicate"), "unknown command 'frobnicate'"));
  EXPECT_EQ(d->execute("# a comment"), "");
  EXPECT_FALSE(d->quit_requested());
  d->execute("quit");
  EXPECT_TRUE(d->quit_requested());
}

// Issue 10 point 5: internal state is readable (print, watch, trace,
// breakpoints) but a write or force is refused, and says why.
TEST(Debugger, InternalStateIsReadableButWritesAndForcesAreRefused) {
  auto d = demo_debugger();
  d->execute("step 5");
  EXPECT_TRUE(has(d->execute("print Tank.hold.running_ Tank.drained.M"), "Tank.hold.running_ = "));
  for (const char* cmd : {"write Tank.hold.start_ T#1s", "force Tank.hold.running_ TRUE",
                          "force Tank.drained.M FALSE", "write Tank.batches.cu_prev_ TRUE"}) {
    const std::string out = d->execute(cmd);
    EXPECT_TRUE(has(out, ": refused, read-only: internal state of its function block")) << out;
  }
  EXPECT_TRUE(has(d->execute("forces"), "no forces"));
  EXPECT_TRUE(has(d->execute("watch Tank.hold.start_"), "Tank.hold.start_ = "));
  EXPECT_TRUE(has(d->execute("break Tank.hold.running_"), "breakpoint 1"));
  EXPECT_TRUE(has(d->execute("trace add Tank.hold.start_"), "Tank.hold.start_"));
  // The interface of the same block stays writable.
  EXPECT_TRUE(has(d->execute("write Tank.hold.PT T#1s"), "will write Tank.hold.PT := T#1s"));
}

// Issue 10 point 7: a duration must be positive and must not run the clock
// past the end of TIME; nothing runs when it is refused.
TEST(Debugger, ContinueForRefusesNonPositiveAndOverflowingDurations) {
  auto d = demo_debugger();
  d->execute("step 3");
  for (const char* cmd :
       {"continue for -5s", "continue for 0s", "continue for T#0ms", "continue for T#-1ns"}) {
    const std::string out = d->execute(cmd);
    EXPECT_TRUE(has(out, "continue for: the duration must be positive")) << cmd << ": " << out;
  }
  std::string out = d->execute("continue for T#200000d");
  EXPECT_TRUE(has(out, "continue for: out of range for TIME")) << out;
  out = d->execute("continue for T#106751d23h47m16s854ms775us807ns");
  EXPECT_TRUE(has(out, "lies beyond the end of TIME")) << out;
  EXPECT_TRUE(has(d->execute("continue for soon"), "not a TIME")) << out;
  EXPECT_TRUE(has(d->execute("continue for"), "usage: continue for DURATION"));
  EXPECT_TRUE(has(d->execute("continue 5s"), "usage: continue [for DURATION]"));
  EXPECT_EQ(d->scan_count(), 3u) << "no refused command ran a scan";
  EXPECT_TRUE(has(d->execute("continue for 2ms"), "ran for T#2ms"));
}

// Issue 10 point 7: `break before PROG hits N` freezes on every N-th call
// of PROG, as `break COND hits N` stops on every N-th hit.
TEST(Debugger, FreezePointHonoursItsHitCount) {
  auto d = demo_debugger();
  std::deque<std::string> script = {"continue", "continue", "quit"};
  std::string printed;
  scripted_io(*d, script, printed);
  EXPECT_TRUE(has(d->execute("break before Tank hits 3"), "before Tank (every 3 hits)"));
  d->execute("continue");
  std::size_t freezes = 0;
  for (std::size_t p = 0;
       (p = printed.find("frozen before program 'Tank'", p)) != std::string::npos; ++p)
    ++freezes;
  EXPECT_EQ(freezes, 3u) << printed;
  EXPECT_TRUE(has(d->execute("breaks"), "before Tank  hits 9 (stops every 3)"))
      << "three freezes, on calls 3, 6 and 9";
  EXPECT_TRUE(has(d->execute("break before Tank hits 0"), "'hits' needs a positive count"));
  EXPECT_TRUE(has(d->execute("break before Tank hits"), "usage: break before PROGRAM"));
  EXPECT_TRUE(has(d->execute("break before Tank hits 2 x"), "usage: break before PROGRAM"));
}

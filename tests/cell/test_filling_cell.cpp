// The example filling cell end to end in virtual time: conveyor (HIWIN E1),
// dosing (PR5510) and the safety interlock (NORD PROFIsafe), driven through
// the debugger's command layer.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <iterator>

#include "../runtime/debugger_deadline.hpp"
#include "plc/cell_config.hpp"
#include "plc/debug/debugger.hpp"
#include "plc_test_paths.hpp"

using namespace plc;

namespace {

std::string cell_path() { return plctest::source_path("programs/filling_cell/cell.yaml"); }

bool has(const std::string& s, const std::string& what) {
  return s.find(what) != std::string::npos;
}

std::unique_ptr<debug::Debugger> cell_debugger() {
  static CellConfig cfg;
  cfg = load_cell_config(cell_path());
  debug::Debugger::Options o;
  o.span = std::chrono::minutes(30);
  return std::make_unique<debug::Debugger>([] { return std::make_unique<Runtime>(cfg); }, o);
}

}  // namespace

TEST(FillingCell, IndexesAndFillsContainersWithinTolerance) {
  auto d = cell_debugger();
  d->execute("continue for 2m");
  const std::string out = d->execute(
      "print Cell.containers Cell.dose.InTolCount Cell.dose.OutTolCount Cell.last_error");
  EXPECT_TRUE(has(out, "Cell.last_error = 16#0000")) << out;
  EXPECT_TRUE(has(out, "Cell.dose.OutTolCount = 0")) << out;
  const VarInfo* n = d->runtime().vars().find("Cell.containers");
  ASSERT_NE(n, nullptr);
  std::int32_t containers = 0;
  VarRegistry::read(*n, &containers);
  EXPECT_GE(containers, 10) << out;
  EXPECT_TRUE(has(out, "Cell.dose.InTolCount = " + std::to_string(containers))) << out;
}

TEST(FillingCell, PassivatingTheSafetyModuleStopsTheConveyorUntilItIsGoodAgain) {
  auto d = cell_debugger();
  d->execute("run until Cell.step = 2");  // indexing: the conveyor is powered
  EXPECT_TRUE(has(d->execute("print Cell.power.Status"), "= TRUE"));
  d->execute("force Cell.guard.FMOD.PASS_ON TRUE");  // the F-program passivates the module
  d->execute("continue for 50ms");
  std::string out = d->execute("print Cell.guard.QBAD Cell.power.Status Cell.step");
  EXPECT_TRUE(has(out, "Cell.guard.QBAD = TRUE")) << out;
  EXPECT_TRUE(has(out, "Cell.power.Status = FALSE"))
      << "no drive enable without the safety module" << out;
  EXPECT_TRUE(has(out, "Cell.step = 0")) << out;
  const std::string before = d->execute("print Cell.containers");
  d->execute("continue for 5s");
  EXPECT_EQ(d->execute("print Cell.containers"), before) << "nothing moves while passivated";
  d->execute("unforce Cell.guard.FMOD.PASS_ON restore");
  d->execute("continue for 10s");
  out = d->execute("print Cell.guard.QBAD Cell.power.Status Cell.last_error");
  EXPECT_TRUE(has(out, "Cell.guard.QBAD = FALSE")) << out;
  EXPECT_NE(d->execute("print Cell.containers"), before) << "the cell runs again";
}

// Record/replay carries the acyclic answers (the F-parameter write of the
// safety module) and the device states, not only the cyclic inputs.
TEST(FillingCell, ARecordingFromTheStartReplaysWithIdenticalOutputs) {
  const std::string rec = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") +
                          "/filling_" + std::to_string(::getpid()) + ".rec";
  {
    auto d = cell_debugger();
    d->execute("record " + rec);
    d->execute("continue for 20s");
    EXPECT_TRUE(has(d->execute("record stop"), "20000 scans"));
  }
  static CellConfig cfg;
  cfg = load_cell_config(cell_path());
  debug::Debugger::Options o;
  o.replay_file = rec;
  debug::Debugger r([] { return std::make_unique<Runtime>(cfg); }, o);
  const std::string out = r.execute("continue");
  EXPECT_TRUE(has(out, "replay 20000 scans, 0 output mismatch(es)")) << out;
  EXPECT_FALSE(has(out, "diverged")) << out;
  EXPECT_TRUE(has(r.execute("print Cell.guard.QBAD"), "= FALSE"))
      << "the F-parameters were answered";
}

// Two virtual-time runs of the whole cell (three device models, acyclic
// traffic, noise in the scale) give identical traces, bit for bit.
TEST(FillingCell, TwoVirtualRunsGiveIdenticalTraces) {
  std::string traces[2];
  for (int i = 0; i < 2; ++i) {
    const std::string file = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") +
                             "/filling_" + std::to_string(::getpid()) + "_" + std::to_string(i) +
                             ".vcd";
    auto d = cell_debugger();
    d->execute(
        "trace add Cell.step Cell.dose.ActualNet Cell.dose.CoarseFeed Cell.dose.FineFeed "
        "Cell.conveyor.ActPosition Cell.guard.FMOD.QBAD %QW0 %IW32");
    ASSERT_TRUE(has(d->execute("trace start " + file), "running into"));
    d->execute("continue for 30s");
    d->execute("trace stop");
    std::ifstream in(file, std::ios::binary);
    traces[i].assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  ASSERT_GT(traces[0].size(), 10000u);
  EXPECT_EQ(traces[0], traces[1]);
  EXPECT_TRUE(has(traces[0], "$scope module dose $end"));
}

// A recording that starts in the middle of the session (mid-batch, mid-index)
// replays exactly: every block declares its internal state in PLC_REFLECT, so
// the snapshot at the recording's first scan holds all of it.
TEST(FillingCell, RecordingsStartedMidSessionReplayExactly) {
  for (const char* start : {"1234ms", "4321ms", "7777ms"}) {
    const std::string rec = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") +
                            "/filling_mid_" + std::to_string(::getpid()) + ".rec";
    {
      auto d = cell_debugger();
      d->execute(std::string("continue for ") + start);
      EXPECT_TRUE(has(d->execute("record " + rec), "starts at scan")) << "the snapshot note";
      d->execute("continue for 9s");
      d->execute("record stop");
    }
    static CellConfig cfg;
    cfg = load_cell_config(cell_path());
    debug::Debugger::Options o;
    o.replay_file = rec;
    debug::Debugger r([] { return std::make_unique<Runtime>(cfg); }, o);
    const std::string out = r.execute("continue");
    EXPECT_TRUE(has(out, "replay 9000 scans, 0 output mismatch(es)"))
        << "from " << start << ": " << out;
    EXPECT_FALSE(has(out, "diverged")) << "from " << start << ": " << out;
  }
}

// The safety module reads the device's diagnosis record every 100 ms
// (acyclic). A recording started while such a request is on its way, or
// after earlier requests were numbered, replayed with "device 'safety' has
// no request 3 waiting": the snapshot held neither the request nor the
// device's request numbering. Now it keeps the numbering and starts at the
// first scan with no request in flight. Every start across one poll period.
TEST(FillingCell, RecordingsStartedDuringAcyclicTrafficReplayExactly) {
  static CellConfig cfg;
  cfg = load_cell_config(cell_path());
  const std::string rec = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") +
                          "/filling_acyc_" + std::to_string(::getpid()) + ".rec";
  int started_later = 0;
  for (int ms = 1195; ms <= 1210; ++ms) {
    std::string stopped;
    {
      auto d = cell_debugger();
      d->execute("continue for " + std::to_string(ms) + "ms");
      d->execute("record " + rec);
      d->execute("continue for 300ms");
      stopped = d->execute("record stop");
    }
    ASSERT_TRUE(has(stopped, "recording stopped, ")) << stopped;
    const std::size_t from = stopped.find(", ") + 2;
    const std::string scans = stopped.substr(from, stopped.find(" scans") - from);
    if (scans != "300") ++started_later;
    debug::Debugger::Options o;
    o.replay_file = rec;
    debug::Debugger r([] { return std::make_unique<Runtime>(cfg); }, o);
    const std::string out = r.execute("continue");
    EXPECT_TRUE(has(out, "replay " + scans + " scans, 0 output mismatch(es)"))
        << "from " << ms << " ms: " << out;
    EXPECT_FALSE(has(out, "diverged")) << "from " << ms << " ms: " << out;
  }
  std::remove(rec.c_str());
  // Some starts fell on a request in flight and waited for the next scan.
  EXPECT_GT(started_later, 0);
}

// Issue 10 point 5: the writes and forces of the issue reached FB-internal
// state and corrupted memory (a PDU length of 2^64-1 overflowed the stack
// buffer in safety_pdu.hpp; a slot of -2^31 read outside the PR5510 arrays).
// They are refused with the reason, the values stay readable, and the cell
// runs on untouched. Run under ASan this also shows nothing reaches memory.
TEST(FillingCell, WritesAndForcesOfBlockInternalsAreRefusedAndTheCellRunsOn) {
  auto d = cell_debugger();
  d->execute("continue for 3s");
  const std::string before = d->execute(
      "print Cell.guard.FMOD.proto_.out_len_ Cell.guard.FMOD.proto_.in_len_ Cell.dose.slot_ "
      "Cell.scale.holder_ Cell.scale.cmd_slot_ Cell.dose.State");
  EXPECT_TRUE(has(before, "Cell.guard.FMOD.proto_.out_len_ = 4  (ULINT)")) << before;
  for (const char* cmd : {
           "force Cell.guard.FMOD.proto_.out_len_ 18446744073709551615",
           "write Cell.guard.FMOD.proto_.in_len_ 4096",
           "write Cell.dose.slot_ -2147483648",
           "force Cell.scale.holder_ 7",
           "write Cell.scale.cmd_slot_ 100",
           "force Cell.scale.rd_code_[3] 9",
           "write Cell.dose.State 3",
           "force Cell.guard.FMOD.phase_ 3",
           "write Cell.conveyor.cmd_id_ 0",
       }) {
    const std::string out = d->execute(cmd);
    EXPECT_TRUE(has(out, ": refused, read-only: internal state of its function block"))
        << cmd << " -> " << out;
  }
  EXPECT_TRUE(has(d->execute("forces"), "no forces"));
  d->execute("continue for 30s");
  const std::string out = d->execute(
      "print Cell.guard.FMOD.proto_.out_len_ Cell.guard.QBAD Cell.last_error "
      "Cell.dose.OutTolCount");
  EXPECT_TRUE(has(out, "Cell.guard.FMOD.proto_.out_len_ = 4  (ULINT)")) << out;
  EXPECT_TRUE(has(out, "Cell.guard.QBAD = FALSE")) << out;
  EXPECT_TRUE(has(out, "Cell.last_error = 16#0000")) << out;
  EXPECT_TRUE(has(out, "Cell.dose.OutTolCount = 0")) << out;
  // The blocks' interfaces stay writable, with values in range.
  EXPECT_TRUE(has(d->execute("write Cell.target_kg 1e39"),
                  "out of range for REAL (-3.40282347e+38 .. 3.40282347e+38): 1e39"));
  EXPECT_TRUE(has(d->execute("force Cell.dose.TolPlus inf"), "infinity is not a REAL value"));
  EXPECT_TRUE(has(d->execute("write Cell.target_kg 19.5"), "will write Cell.target_kg := 19.5"));
}

// Real time on the bench (issue 10): a recording made in real time, with
// the logic paused at breakpoints, single steps, and the safety module
// forced to passivate and released again, replays with no difference.
// (Before, every recorded scan time was 0 and about 2,600 of 3,000 scans
// replayed differently.) Real time because that is what it checks; it
// asserts nothing about timing and passes without SCHED_FIFO.
TEST(FillingCell, ARealTimeRecordingWithPausesAndForcesReplaysBitExact) {
  static CellConfig cfg;
  cfg = load_cell_config(cell_path());
  const std::string rec = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") +
                          "/filling_rt_" + std::to_string(::getpid()) + ".rec";
  std::string stopped;
  {
    debug::Debugger::Options o;
    o.mode = io::ClockMode::RealTime;
    o.span = std::chrono::minutes(1);
    debug::Debugger d([] { return std::make_unique<Runtime>(cfg); }, o);
    plctest::Deadline deadline(d);
    EXPECT_TRUE(has(d.execute("record " + rec), "recording every scan's inputs"));
    for (const char* c :
         {"run until Cell.step = 2", "force Cell.guard.FMOD.PASS_ON TRUE",
          "run until Cell.power.Status = FALSE", "step 20",
          "unforce Cell.guard.FMOD.PASS_ON restore", "run until Cell.power.Status = TRUE",
          "run until Cell.dose.State = 2", "run until Cell.dose.ActualNet > 4.0"}) {
      const std::string out = d.execute(c);
      EXPECT_FALSE(has(out, "unknown") || has(out, "usage")) << c << ": " << out;
    }
    stopped = d.execute("record stop");
    d.execute("quit");
  }
  ASSERT_TRUE(has(stopped, "recording stopped, ")) << stopped;
  const std::size_t from = stopped.find(", ") + 2;
  const std::string scans = stopped.substr(from, stopped.find(" scans") - from);
  EXPECT_GT(std::stoul(scans), 500u) << stopped;
  debug::Debugger::Options o;
  o.replay_file = rec;
  debug::Debugger r([] { return std::make_unique<Runtime>(cfg); }, o);
  const std::string out = r.execute("continue");
  EXPECT_TRUE(has(out, "replay " + scans + " scans, 0 output mismatch(es)")) << stopped << out;
  EXPECT_FALSE(has(out, "diverged")) << out;
  std::remove(rec.c_str());
}

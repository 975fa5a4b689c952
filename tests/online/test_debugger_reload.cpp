// The debugger's `reload` command (online change from the console), in
// virtual time: the cell is between scans when the command runs, so every
// task switches at once; breakpoint conditions and the trace set-up follow
// the variables into the new build.
#include "online_fixture.hpp"
#include "plc/debug/debugger.hpp"

namespace plc::test {
namespace {

bool has(const std::string& out, const std::string& what) {
  return out.find(what) != std::string::npos;
}

std::unique_ptr<debug::Debugger> debugger(const CellFolder& folder) {
  static CellConfig cfg;
  cfg = folder.config();
  debug::Debugger::Options o;
  o.span = std::chrono::minutes(10);
  return std::make_unique<debug::Debugger>([] { return std::make_unique<Runtime>(cfg); }, o);
}

TEST(DebuggerReload, SwitchesBetweenScansAndKeepsBreakpoints) {
  CellFolder folder;
  folder.install(PLC_TEST_FILLER_V1);
  auto d = debugger(folder);
  d->execute("step 100");
  EXPECT_TRUE(has(d->execute("print Main.step"), "1")) << d->execute("print Main.step");
  const std::string weight = d->execute("print Main.weight");
  d->execute("break Main.step = 3");
  d->execute("trace add Main.weight");

  folder.install(PLC_TEST_FILLER_V2);
  const std::string out = d->execute("reload");
  EXPECT_TRUE(has(out, "added (initial value): Main.alarms: DINT")) << out;
  EXPECT_TRUE(has(out, "removed (value dropped): Main.note: INT")) << out;
  EXPECT_TRUE(has(out, "switched")) << out;
  // Nothing ran yet: the state is the one before the command.
  EXPECT_EQ(d->execute("print Main.weight"), weight);
  d->execute("step 1");
  EXPECT_TRUE(has(d->execute("print Main.build"), "= 2")) << d->execute("print Main.build");
  // The breakpoint's condition now reads the new program's field.
  const std::string stop = d->execute("continue");
  EXPECT_TRUE(has(d->execute("print Main.step"), "= 3")) << stop;
}

TEST(DebuggerReload, RefusedBeforeARecordingStartsAndForAFailedLoad) {
  CellFolder folder;
  folder.install(PLC_TEST_FILLER_V1);
  auto d = debugger(folder);
  d->execute("step 10");
  folder.install(PLC_TEST_FILLER_ABI999);
  const std::string out = d->execute("reload");
  EXPECT_TRUE(has(out, "online change refused: cannot load")) << out;
  EXPECT_TRUE(has(out, "ABI version 999")) << out;
  d->execute("step 1");
  EXPECT_TRUE(has(d->execute("print Main.build"), "= 1"));
  const std::string rec =
      (fs::temp_directory_path() / ("softplc-reload-" + std::to_string(getpid()) + ".rec"))
          .string();
  // A recording begins at the next latch, with a snapshot of the build
  // then running: a change before that is refused (recording.hpp).
  d->execute("record " + rec);
  folder.install(PLC_TEST_FILLER_V2);
  EXPECT_TRUE(has(d->execute("reload"), "step a scan first"));
  d->execute("step 1");
  EXPECT_TRUE(has(d->execute("reload"), "switched"));
  d->execute("record stop");
  fs::remove_all(rec + ".libs");
  fs::remove(rec);
}

// A force on a field the new build removed (note) or retyped (flow: REAL ->
// LREAL) is dropped and listed: its value no longer has a place to go (it
// used to keep pointing into the destroyed old program). The force on a
// field kept by path and type goes on in the new build. So does a
// breakpoint whose condition reads a removed field (it is deleted).
TEST(DebuggerReload, ForcesOnRemovedOrRetypedFieldsAreDropped) {
  CellFolder folder;
  folder.install(PLC_TEST_FILLER_V1);
  auto d = debugger(folder);
  d->execute("step 5");
  d->execute("force Main.note 5");
  d->execute("force Main.flow 0.25");
  d->execute("force Main.target 7.5");
  d->execute("break Main.note = 99");
  folder.install(PLC_TEST_FILLER_V2);
  const std::string out = d->execute("reload");
  EXPECT_TRUE(has(out, "(Main.note = 99) deleted: its condition does not compile")) << out;
  EXPECT_TRUE(has(out, "force on Main.note dropped: the new build has no such variable")) << out;
  EXPECT_TRUE(has(out, "force on Main.flow dropped: its type changed")) << out;
  d->execute("step 5");
  const std::string forces = d->execute("forces");
  EXPECT_FALSE(has(forces, "Main.note")) << forces;
  EXPECT_FALSE(has(forces, "Main.flow")) << forces;
  EXPECT_TRUE(has(forces, "Main.target")) << forces;
  EXPECT_TRUE(has(d->execute("print Main.target"), "= 7.5"));
  EXPECT_TRUE(has(d->execute("print Main.flow"), "= 0.125"));
}

}  // namespace
}  // namespace plc::test

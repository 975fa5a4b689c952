// Online change (issue 15, "Online change"): a new build of a program
// library replaces the running programs at a scan boundary of each task
// concerned; state moves over by path and type; changes that cannot be
// applied are refused and the old code runs on. Virtual time throughout.
#include <array>
#include <vector>

#include "online_fixture.hpp"
#include "plc/online_change.hpp"

namespace plc::test {
namespace {

// The state a batch carries: compared scan by scan with a reference cell
// that never changes, so any jump at the switch shows as a difference.
const std::array<const char*, 10> kState = {
    "Main.step",         "Main.weight",     "Main.settle.ET", "Main.settle.start_", "Main.dwell.ET",
    "Main.dwell.start_", "Main.batches.CV", "Other.weight",   "Other.dwell.ET",     "Main.lamp"};

std::vector<std::string> row(const Runtime& rt) {
  std::vector<std::string> r;
  for (const char* p : kState) r.push_back(value(rt, p));
  return r;
}

struct Cell {
  CellFolder folder;
  std::unique_ptr<Runtime> rt;
  explicit Cell(const char* built) {
    folder.install(built);
    rt = std::make_unique<Runtime>(folder.config());
    rt->start(io::ClockMode::Virtual);
  }
};

// Runs `cell` and `ref` in lockstep until `when` holds in `cell`; every row
// of the state must match on the way. Bounded by `max_scans`.
template <class When>
bool run_until(Cell& cell, Cell& ref, When when, int max_scans) {
  for (int i = 0; i < max_scans; ++i) {
    if (when(*cell.rt)) return true;
    cell.rt->step_scan();
    ref.rt->step_scan();
    EXPECT_EQ(row(*cell.rt), row(*ref.rt)) << "at " << cell.rt->now().count() << " ns";
  }
  return false;
}

void online_change_keeps_state(bool (*switch_point)(const Runtime&)) {
  Cell cell(PLC_TEST_FILLER_V1);
  Cell ref(PLC_TEST_FILLER_V1);
  ASSERT_TRUE(run_until(cell, ref, switch_point, 5000));
  ASSERT_EQ(value(*cell.rt, "Main.build"), "1");

  cell.folder.install(PLC_TEST_FILLER_V2);  // the user's new build
  OnlineChange change(*cell.rt);
  const ChangeReport report = change.prepare("");
  ASSERT_EQ(report.refused, "");
  // The report, before the switch: what is added, removed, retyped.
  EXPECT_EQ(report.programs, (std::vector<std::string>{"Main (Filler)", "Other (Filler)"}));
  EXPECT_EQ(report.added, (std::vector<std::string>{"Main.alarms: DINT", "Other.alarms: DINT"}));
  EXPECT_EQ(report.removed, (std::vector<std::string>{"Main.note: INT", "Other.note: INT"}));
  EXPECT_EQ(report.retyped,
            (std::vector<std::string>{"Main.flow: REAL -> LREAL", "Other.flow: REAL -> LREAL"}));
  EXPECT_EQ(value(*cell.rt, "Main.build"), "1");  // nothing switched yet

  change.commit();
  // Each task switches at its own next scan; the fast task (10 ms) scans
  // several times before the slow one (50 ms) reaches its boundary.
  bool saw_half = false;
  for (int i = 0; i < 20 && !change.switched(); ++i) {
    cell.rt->step_scan();
    ref.rt->step_scan();
    // One task switched, the other not yet.
    saw_half = saw_half || ((cell.rt->tasks()[0]->swap.load() == nullptr) !=
                            (cell.rt->tasks()[1]->swap.load() == nullptr));
  }
  ASSERT_TRUE(change.switched());
  EXPECT_TRUE(saw_half) << "the two tasks switched together, not each at its own boundary";
  change.finish();

  // New code runs (build 2), the new field has its initial value, the
  // removed one is gone, and the state went on as if nothing had happened.
  EXPECT_EQ(value(*cell.rt, "Main.build"), "2");
  EXPECT_EQ(value(*cell.rt, "Main.alarms"), "7");
  EXPECT_EQ(cell.rt->vars().find("Main.note"), nullptr);
  EXPECT_EQ(row(*cell.rt), row(*ref.rt));
  // And goes on doing so through the next batches (3 fill cycles).
  run_until(
      cell, ref, [](const Runtime&) { return false; }, 1500);
  EXPECT_EQ(value(*cell.rt, "Main.batches.CV"), value(*ref.rt, "Main.batches.CV"));
  EXPECT_NE(value(*cell.rt, "Main.batches.CV"), "0");
}

TEST(OnlineChange, BatchMidFillAndRunningTimerCarryOver) {
  online_change_keeps_state([](const Runtime& rt) {
    return value(rt, "Main.step") == "1" && value(rt, "Main.weight") == "12.5";
  });
}

TEST(OnlineChange, SettleTimerRunningCarriesOver) {
  online_change_keeps_state([](const Runtime& rt) {
    return value(rt, "Main.step") == "2" && value(rt, "Main.settle.ET") == "T#100ms";
  });
}

// Issue 21 follow-up, point 5: Program::init() runs on the programs an
// online change creates, before the values carry over (CODESYS: FB_init
// with bInCopyCode = TRUE, then the copy): version 2's init() gives the new
// field `alarms` its value 7 and sets `weight` to -1, but the running
// batch's weight carries over it.
TEST(OnlineChange, InitRunsOnTheNewProgramsBeforeTheValuesCarryOver) {
  Cell cell(PLC_TEST_FILLER_V1);
  for (int i = 0; i < 30; ++i) cell.rt->step_scan();
  const std::string weight = value(*cell.rt, "Main.weight");
  ASSERT_NE(weight, "0");
  cell.folder.install(PLC_TEST_FILLER_V2);
  OnlineChange change(*cell.rt);
  ASSERT_EQ(change.prepare("").refused, "");
  change.switch_all_now();
  ASSERT_TRUE(change.switched());
  change.finish();
  EXPECT_EQ(value(*cell.rt, "Main.alarms"), "7");  // init() ran
  EXPECT_EQ(value(*cell.rt, "Other.alarms"), "7");
  EXPECT_EQ(value(*cell.rt, "Main.weight"), weight);  // carried over init()'s -1
}

// A refused or failed change leaves the cell exactly as it was.
void refused_leaves_cell_alone(const char* built, const std::string& reason_part,
                               bool remove_file = false) {
  Cell cell(PLC_TEST_FILLER_V1);
  Cell ref(PLC_TEST_FILLER_V1);
  ASSERT_TRUE(run_until(
      cell, ref, [](const Runtime& rt) { return value(rt, "Main.step") == "1"; }, 100));
  if (remove_file)
    fs::remove(cell.folder.library());
  else
    cell.folder.install(built);
  const std::size_t nvars = cell.rt->vars().all().size();
  OnlineChange change(*cell.rt);
  const ChangeReport report = change.prepare(cell.folder.library());
  EXPECT_NE(report.refused.find(reason_part), std::string::npos) << report.refused;
  change.commit();  // nothing to hand over
  EXPECT_FALSE(change.switched());
  EXPECT_EQ(cell.rt->vars().all().size(), nvars);
  run_until(
      cell, ref, [](const Runtime&) { return false; }, 300);
  EXPECT_EQ(value(*cell.rt, "Main.build"), "1");
}

TEST(OnlineChange, RefusedWhenLocatedVariableMoved) {
  refused_leaves_cell_alone(PLC_TEST_FILLER_V3,
                            "located variable Main.lamp moved from %QX0.0 BOOL to %QX0.1 BOOL");
}

TEST(OnlineChange, RefusedWhenConstructorThrows) {
  refused_leaves_cell_alone(PLC_TEST_FILLER_V4,
                            "program 'Main': the constructor of Filler threw: bad version 4");
}

TEST(OnlineChange, FailedLoadMissingFileLeavesCellAlone) {
  refused_leaves_cell_alone(nullptr, "no such file", true);
}

TEST(OnlineChange, FailedLoadUndefinedSymbolLeavesCellAlone) {
  refused_leaves_cell_alone(PLC_TEST_FILLER_V5, "undefined symbol: softplc_test_symbol");
}

TEST(OnlineChange, AbiMismatchLeavesCellAlone) {
  refused_leaves_cell_alone(PLC_TEST_FILLER_ABI999, "built against softplc ABI version 999");
}

TEST(OnlineChange, RefusedForALibraryTheCellDoesNotLoad) {
  Cell cell(PLC_TEST_FILLER_V1);
  OnlineChange change(*cell.rt);
  EXPECT_NE(
      change.prepare("/nowhere/libother.so").refused.find("is not one of the cell's libraries"),
      std::string::npos);
}

}  // namespace
}  // namespace plc::test

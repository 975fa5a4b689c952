// Online change of programs with RETAIN/PERSISTENT fields (issue 21, point
// 5), in virtual time: retained values move over by path and type like
// every other field, the report lists what the retain file gains and loses
// as a restart does, and the retain file switches layout at the scan
// boundary where the last task concerned switches (retain::Manager). Two
// tasks, fast (10 ms, program A) and slow (50 ms, program B), both Keepers
// (keeper_program.cpp).
#include <condition_variable>
#include <fstream>
#include <functional>
#include <iterator>
#include <mutex>

#include "online_fixture.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/online_change.hpp"
#include "plc/retain/retain_file.hpp"
#include "plc/retain/retain_manager.hpp"

namespace plc::test {
namespace {

std::string keeper_yaml(const std::string& save_every) {
  return R"(
cell: keep
libraries: [libfiller.so]
image: {memory: 8}
retain: {file: keep.retain, save_every: )" +
         save_every + R"(, memory: ["%MB0..%MB3"]}
tasks:
  - name: fast
    period: 10ms
    programs: [A]
  - name: slow
    period: 50ms
    programs: [B]
programs:
  - name: A
    type: Keeper
  - name: B
    type: Keeper
)";
}

// The cell with its retain manager, started (Auto) in virtual time.
// `setup` runs on the manager before its start (a test hook on the writer).
struct KeeperCell {
  CellFolder folder;
  CellConfig cfg;
  std::unique_ptr<Runtime> rt;
  std::unique_ptr<retain::Manager> mgr;
  retain::StartReport start;
  explicit KeeperCell(const char* built, const std::string& save_every = "10ms",
                      const std::function<void(retain::Manager&)>& setup = {}) {
    folder.install(built);
    cfg = parse_cell_config(keeper_yaml(save_every), folder.config_file());
    boot(setup);
  }
  void boot(const std::function<void(retain::Manager&)>& setup = {}) {
    rt = std::make_unique<Runtime>(cfg);
    mgr = std::make_unique<retain::Manager>(*rt, cfg.retain);
    if (setup) setup(*mgr);
    start = mgr->start(retain::StartMode::Auto);
    rt->start(io::ClockMode::Virtual);
  }
  ~KeeperCell() {
    if (rt) rt->finish();
    if (mgr) mgr->stop();
  }
  void scans(int n) {
    for (int i = 0; i < n; ++i) rt->step_scan();
  }
  [[nodiscard]] std::string v(const std::string& path) const { return value(*rt, path); }
  [[nodiscard]] std::string file() const { return cfg.retain.path; }
};

std::optional<retain::FileImage> read_copy(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<std::uint8_t> b((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
  std::string why;
  auto img = retain::decode(b, why);
  EXPECT_TRUE(img) << file << ": " << why;
  return img;
}

bool has_entry(const retain::FileImage& img, const std::string& path) {
  for (const auto& e : img.entries)
    if (e.path == path) return true;
  return false;
}

// Until now a program with retained fields was refused ("the retain file's
// layout is fixed while the cell runs"). The report lists the retained
// variables as a restart lists the file's layout differences.
TEST(OnlineRetain, RetainedProgramChangesAndTheReportListsTheRetainedDifferences) {
  KeeperCell cell(PLC_TEST_KEEPER_V1);
  cell.scans(20);
  cell.folder.install(PLC_TEST_KEEPER_V2);
  OnlineChange change(*cell.rt);
  const ChangeReport r = change.prepare("");
  ASSERT_EQ(r.refused, "");
  EXPECT_EQ(r.retain_added, (std::vector<std::string>{"A.extra: LINT", "A.plain: DINT",
                                                      "B.extra: LINT", "B.plain: DINT"}));
  EXPECT_EQ(r.retain_removed, (std::vector<std::string>{"A.note: INT", "B.note: INT"}));
  EXPECT_EQ(r.retain_retyped,
            (std::vector<std::string>{"A.level: REAL -> LREAL", "B.level: REAL -> LREAL"}));
  // count, twin, recipe (PERSISTENT), parts.{CU,R,PV,Q,CV,cu_prev_}: 9 per program.
  EXPECT_EQ(r.retain_kept, 18u);
  const std::string text = r.text();
  EXPECT_NE(text.find("  retained (RETAIN/PERSISTENT): 18 keep their values and their place in "
                      "the retain file\n  retained, new in the retain file: A.extra: LINT\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("  retained, type changed in the retain file: A.level: REAL -> LREAL\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("  retained no more (dropped from the retain file): A.note: INT\n"),
            std::string::npos)
      << text;

  // The values move over like every other field's.
  const std::string count = cell.v("A.count"), cv = cell.v("A.parts.CV");
  const std::string plain = cell.v("A.plain");
  change.switch_all_now();
  change.finish();
  EXPECT_EQ(cell.v("A.count"), count);
  EXPECT_EQ(cell.v("A.parts.CV"), cv);
  EXPECT_EQ(cell.v("A.extra"), "5");    // new: initial value
  EXPECT_EQ(cell.v("A.level"), "2.5");  // retyped: initial value
  EXPECT_EQ(cell.v("A.plain"), plain);  // newly retained, same type: carried
  EXPECT_EQ(cell.v("A.recipe"), "7");
}

// Issue 21 follow-up, point 3: nobody asks the manager to follow a change;
// the change tells it (Runtime::add_change_observer), so the layout after
// finish() is the new build's and no save reads the destroyed old programs.
TEST(OnlineRetain, TheRuntimeTellsTheRetainManagerOfEveryChange) {
  KeeperCell cell(PLC_TEST_KEEPER_V1);
  cell.scans(20);
  const std::uint64_t old_hash = cell.mgr->layout().hash();
  cell.folder.install(PLC_TEST_KEEPER_V2);
  {
    OnlineChange change(*cell.rt);
    ASSERT_EQ(change.prepare("").refused, "");
    change.switch_all_now();
    ASSERT_TRUE(change.switched());
    change.finish();  // the old programs are gone
  }
  EXPECT_NE(cell.mgr->layout().hash(), old_hash);
  bool has_extra = false;
  for (const auto& e : cell.mgr->layout().entries()) has_extra |= e.path == "A.extra";
  EXPECT_TRUE(has_extra) << "the manager still saves the old build's layout";
  cell.scans(20);
  cell.rt->finish();
  ASSERT_EQ(cell.mgr->stop(), "");
  const auto loaded = retain::Storage(cell.file()).load();
  ASSERT_TRUE(loaded.image);
  EXPECT_TRUE(has_entry(*loaded.image, "A.extra"));
  EXPECT_FALSE(has_entry(*loaded.image, "A.note"));
}

// The retain file follows the change: no file mixes layouts, the switch is
// made when the last task concerned switched, and the next save is in the
// new layout; a warm start of the new build restores everything, and one
// from the old layout's copy restores by path and type.
TEST(OnlineRetain, RetainFileSwitchesLayoutWhenTheLastTaskSwitched) {
  KeeperCell cell(PLC_TEST_KEEPER_V1);
  cell.scans(30);
  const std::uint64_t old_hash = cell.mgr->layout().hash();
  cell.folder.install(PLC_TEST_KEEPER_V2);
  OnlineChange change(*cell.rt);
  ASSERT_EQ(change.prepare("").refused, "");
  EXPECT_EQ(cell.mgr->layout().hash(), old_hash);  // prepared, not switched
  change.commit();
  // The fast task switches at its next scan, the slow one up to 50 ms later:
  // in between the snapshots stay in the old layout.
  bool saw_half = false;
  for (int i = 0; i < 20 && !change.switched(); ++i) {
    cell.rt->step_scan();
    if (change.switched(0) && !change.switched(1)) {
      saw_half = true;
      EXPECT_EQ(cell.mgr->layout().hash(), old_hash) << "switched before the slow task did";
    }
  }
  ASSERT_TRUE(change.switched());
  ASSERT_TRUE(saw_half) << "the two tasks switched together";
  const std::uint64_t new_hash = cell.mgr->layout().hash();
  EXPECT_NE(new_hash, old_hash);
  EXPECT_NE(cell.mgr->layout().entries().size(), 0u);
  change.finish();
  cell.scans(20);
  const std::string count_a = cell.v("A.count"), count_b = cell.v("B.count");
  cell.rt->finish();
  ASSERT_EQ(cell.mgr->stop(), "");
  const auto loaded = retain::Storage(cell.file()).load();
  ASSERT_TRUE(loaded.image);
  EXPECT_TRUE(loaded.problems.empty());
  EXPECT_EQ(loaded.image->layout_hash, new_hash);
  EXPECT_TRUE(has_entry(*loaded.image, "A.extra"));
  EXPECT_TRUE(has_entry(*loaded.image, "B.plain"));
  EXPECT_FALSE(has_entry(*loaded.image, "A.note"));
  // Every copy written is of one layout: decoded, its hash is one of the two.
  for (const char* ext : {".a", ".b"}) {
    const auto img = read_copy(cell.file() + ext);
    ASSERT_TRUE(img);
    EXPECT_TRUE(img->layout_hash == old_hash || img->layout_hash == new_hash);
    EXPECT_EQ(has_entry(*img, "A.note"), img->layout_hash == old_hash);
    EXPECT_EQ(has_entry(*img, "A.extra"), img->layout_hash == new_hash);
  }

  // A warm start of the new build: the same layout, everything restored.
  cell.mgr.reset();
  cell.rt.reset();
  cell.boot();
  EXPECT_EQ(cell.start.mode, retain::StartMode::Warm);
  EXPECT_TRUE(cell.start.added.empty() && cell.start.removed.empty() &&
              cell.start.type_changed.empty());
  EXPECT_EQ(cell.v("A.count"), count_a);
  EXPECT_EQ(cell.v("B.count"), count_b);
  EXPECT_EQ(cell.v("A.build"), "2");
}

// A snapshot the writer took before the switch but writes after it is
// written whole in its own (old) layout; the next one is in the new layout.
TEST(OnlineRetain, SnapshotOfferedBeforeTheSwitchIsWrittenInItsOwnLayout) {
  // The disk hangs in the first write until released (bounded: a broken
  // test ends after 30 s instead of hanging).
  std::mutex mu;
  std::condition_variable cv;
  bool released = false;
  KeeperCell cell(PLC_TEST_KEEPER_V1, "1h", [&](retain::Manager& m) {
    m.writer().set_before_write([&] {
      std::unique_lock<std::mutex> lock(mu);
      cv.wait_for(lock, std::chrono::seconds(30), [&] { return released; });
    });
  });
  cell.scans(3);  // the first snapshot (both tasks at t = 0) went to the writer, which hangs
  ASSERT_EQ(cell.mgr->stats().offered, 1u);
  const std::uint64_t old_hash = cell.mgr->layout().hash();

  cell.folder.install(PLC_TEST_KEEPER_V2);
  OnlineChange change(*cell.rt);
  ASSERT_EQ(change.prepare("").refused, "");
  change.switch_all_now();  // between scans: every task at once
  ASSERT_TRUE(change.switched());
  change.finish();
  const std::uint64_t new_hash = cell.mgr->layout().hash();
  ASSERT_NE(new_hash, old_hash);
  cell.scans(10);
  {
    std::lock_guard<std::mutex> lock(mu);
    released = true;
  }
  cv.notify_all();
  cell.rt->finish();
  ASSERT_EQ(cell.mgr->stop(), "");  // the hung write (sequence 1), then the final one (2)
  EXPECT_EQ(cell.mgr->stats().written, 2u);
  EXPECT_GE(cell.mgr->stats().skipped, 1u);  // the new layout's snapshots while it hung
  const auto first = read_copy(cell.file() + ".a");
  const auto last = read_copy(cell.file() + ".b");
  ASSERT_TRUE(first && last);
  EXPECT_EQ(first->sequence, 1u);
  EXPECT_EQ(first->layout_hash, old_hash);
  EXPECT_TRUE(has_entry(*first, "A.note"));
  EXPECT_FALSE(has_entry(*first, "A.extra"));
  EXPECT_EQ(last->sequence, 2u);
  EXPECT_EQ(last->layout_hash, new_hash);
  EXPECT_TRUE(has_entry(*last, "A.extra"));
  cell.mgr.reset();
  cell.rt.reset();
}

// The debugger's `reload` with the cell's retain manager (plcrun in a
// session that loads and saves retain data): the report says what the file
// gains and loses and that it follows; the next save is in the new layout.
TEST(OnlineRetain, DebuggerReloadSwitchesTheRetainFile) {
  CellFolder folder;
  folder.install(PLC_TEST_KEEPER_V1);
  static CellConfig cfg;
  cfg = parse_cell_config(keeper_yaml("10ms"), folder.config_file());
  std::unique_ptr<retain::Manager> mgr;
  debug::Debugger::Options o;
  o.span = std::chrono::minutes(10);
  o.on_build = [&](Runtime& rt) {
    mgr = std::make_unique<retain::Manager>(rt, cfg.retain);
    mgr->start(retain::StartMode::Auto);
  };
  auto d = std::make_unique<debug::Debugger>([] { return std::make_unique<Runtime>(cfg); }, o);
  d->set_retain(mgr.get());
  d->execute("step 10");
  folder.install(PLC_TEST_KEEPER_V2);
  const std::string out = d->execute("reload");
  EXPECT_NE(out.find("retained, new in the retain file: A.extra: LINT"), std::string::npos) << out;
  EXPECT_NE(out.find("the retain file is saved in the new layout"), std::string::npos) << out;
  EXPECT_NE(out.find("switched: every task concerned runs the new build"), std::string::npos)
      << out;
  d->execute("step 10");
  d->stop_cell();
  ASSERT_EQ(mgr->stop(), "");
  const auto loaded = retain::Storage(cfg.retain.path).load();
  ASSERT_TRUE(loaded.image);
  EXPECT_TRUE(has_entry(*loaded.image, "A.extra"));
  EXPECT_FALSE(has_entry(*loaded.image, "A.note"));
  mgr.reset();
}

}  // namespace
}  // namespace plc::test

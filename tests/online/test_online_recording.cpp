// Record and replay across an online change (plc/debug/recording.hpp,
// "Online change during a recording"; issue 15, "Record/replay and the
// debugger keep working across a change; a recording notes the change").
// Virtual time: the debugger's `reload` switches every task between scans.
#include "online_fixture.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/debug/recording.hpp"

namespace plc::test {
namespace {

bool has(const std::string& out, const std::string& what) {
  return out.find(what) != std::string::npos;
}

std::unique_ptr<debug::Debugger> debugger(const CellConfig& cfg, const std::string& replay = "") {
  debug::Debugger::Options o;
  o.span = std::chrono::minutes(10);
  o.replay_file = replay;
  return std::make_unique<debug::Debugger>([cfg] { return std::make_unique<Runtime>(cfg); }, o);
}

const std::vector<std::string> kState = {"Main.build",   "Main.step",   "Main.weight",
                                         "Main.alarms",  "Main.flow",   "Other.step",
                                         "Other.weight", "Other.build", "Main.batches.CV"};

std::vector<std::string> state(const Runtime& rt) {
  std::vector<std::string> s;
  for (const auto& p : kState) s.push_back(p + " = " + value(rt, p));
  return s;
}

// A session recorded from scan 20, with v1 -> v2 switched at scan 50.
struct RecordedSession {
  std::string rec;
  std::string reload;
  std::vector<std::string> final_state;
  std::uint64_t scans = 0;
};

RecordedSession record_across_change(CellFolder& folder, const CellConfig& cfg) {
  RecordedSession s;
  s.rec = (fs::path(folder.library()).parent_path() / "session.rec").string();
  folder.install(PLC_TEST_FILLER_V1);
  auto d = debugger(cfg);
  d->execute("step 20");
  EXPECT_TRUE(has(d->execute("record " + s.rec), "recording")) << s.rec;
  d->execute("step 30");
  folder.install(PLC_TEST_FILLER_V2);
  s.reload = d->execute("reload");
  d->execute("step 60");
  EXPECT_TRUE(has(d->execute("print Main.build"), "= 2"));
  const std::string stopped = d->execute("record stop");
  EXPECT_TRUE(has(stopped, "recording stopped")) << stopped;
  s.final_state = state(d->runtime());
  return s;
}

TEST(OnlineRecording, ReplayMakesTheRecordedChangeAtTheSameScanBitForBit) {
  CellFolder folder;
  const CellConfig cfg = folder.config();
  const RecordedSession s = record_across_change(folder, cfg);
  ASSERT_TRUE(has(s.reload, "switched")) << s.reload;
  // The recording notes the start build and the change (one per task).
  {
    debug::RecordingReader reader(s.rec);
    debug::Record r;
    std::vector<std::pair<std::uint16_t, std::uint32_t>> changes;
    std::uint64_t change_scan = 0;
    while (reader.next(r))
      if (r.type == debug::recfmt::kChange) {
        changes.emplace_back(r.task, r.change);
        if (r.change == 1) {
          change_scan = r.scan;
          EXPECT_EQ(std::string(r.library), folder.library());
          EXPECT_TRUE(has(std::string(r.report), "added (initial value): Main.alarms: DINT"));
        }
      }
    const std::vector<std::pair<std::uint16_t, std::uint32_t>> want = {
        {debug::recfmt::kNoTask, 0}, {0, 1}, {1, 1}};
    EXPECT_EQ(changes, want);
    EXPECT_GT(change_scan, 0u);
  }
  // The file at the library's path is v2 now, and so is the process's
  // current build: the replay starts from the recording's copy of v1.
  auto rt = std::make_unique<Runtime>(cfg);
  EXPECT_EQ(value(*rt, "Main.alarms"), "7");  // a field of v2 only
  debug::Replayer replay(*rt, s.rec);
  EXPECT_EQ(value(*rt, "Main.alarms"), "<none: Main.alarms>");
  EXPECT_EQ(value(*rt, "Main.note"), "42");  // of v1 only
  std::uint64_t steps = 0;
  while (replay.step() && ++steps < 100000) {
  }
  EXPECT_EQ(replay.error(), "");
  EXPECT_TRUE(replay.at_end());
  EXPECT_EQ(replay.scans(), replay.total_scans());
  EXPECT_EQ(replay.mismatches(), 0u) << "first at scan " << replay.first_mismatch();
  EXPECT_EQ(state(*rt), s.final_state);
}

TEST(OnlineRecording, ReplayRefusedWhenTheRecordedBuildIsGone) {
  CellFolder folder;
  const CellConfig cfg = folder.config();
  const RecordedSession s = record_across_change(folder, cfg);
  ASSERT_TRUE(has(s.reload, "switched")) << s.reload;
  // Another build at the path, and the recording's copies gone.
  fs::remove_all(s.rec + ".libs");
  folder.install(PLC_TEST_FILLER_V3);
  auto rt = std::make_unique<Runtime>(cfg);
  try {
    debug::Replayer replay(*rt, s.rec);
    FAIL() << "replay accepted a recording whose library builds are gone";
  } catch (const debug::RecordingError& e) {
    EXPECT_TRUE(has(e.what(), "put that build back")) << e.what();
    EXPECT_TRUE(has(e.what(), folder.library())) << e.what();
  }
}

TEST(OnlineRecording, GotoBackAcrossAChange) {
  CellFolder folder;
  const CellConfig cfg = folder.config();
  const RecordedSession s = record_across_change(folder, cfg);
  ASSERT_TRUE(has(s.reload, "switched")) << s.reload;
  // In the live session that made the change: refused, with the reason.
  {
    folder.install(PLC_TEST_FILLER_V1);
    auto d = debugger(cfg);
    d->execute("step 10");
    folder.install(PLC_TEST_FILLER_V2);
    ASSERT_TRUE(has(d->execute("reload"), "switched"));
    d->execute("step 10");
    const std::string out = d->execute("goto 5");
    EXPECT_TRUE(has(out, "needs the old build")) << out;
    EXPECT_TRUE(has(d->execute("print Main.build"), "= 2"));
  }
  // In the replay: back before the change runs the old build again.
  auto r = debugger(cfg, s.rec);
  const std::string end = r->execute("continue");
  EXPECT_TRUE(has(end, "0 output mismatch(es)")) << end;
  EXPECT_TRUE(has(r->execute("print Main.build"), "= 2"));
  r->execute("goto 2");
  EXPECT_TRUE(has(r->execute("print Main.build"), "= 1")) << r->execute("print Main.build");
  const std::string again = r->execute("continue");
  EXPECT_TRUE(has(again, "0 output mismatch(es)")) << again;
  EXPECT_FALSE(has(again, "diverged")) << again;
  EXPECT_TRUE(has(r->execute("print Main.build"), "= 2"));
}

}  // namespace
}  // namespace plc::test

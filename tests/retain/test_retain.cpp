// Retain and persistent variables (issue 14): start-up modes as IEC 61131-3
// defines them (ed.3 6.5.6 / 2.4.3.1: RETAIN kept over a warm start,
// PERSISTENT also over a cold start), layout changes, damaged files, a full
// disk, and a stalled disk that must never hold up a scan. Virtual time.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <mutex>

#include "../runtime/test_helpers.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/retain/retain_manager.hpp"
#include "retain_programs.hpp"

namespace {

using namespace plc;
using plc::retain::StartMode;

std::string cell_yaml(const std::string& file, const std::string& type = "RetainProbe",
                      const std::string& save_every = "1h") {
  return "cell: r\nimage: {inputs: 8, outputs: 8, memory: 32}\n"
         "tasks: [{name: main, period: 1ms, programs: [P]}]\n"
         "programs: [{name: P, type: " +
         type + "}]\nretain: {file: " + file + ", save_every: " + save_every +
         ", memory: [\"%MB20..%MB23\"]}\n";
}

// One run of the cell: start-up in `mode`, `scans` scans, controlled stop.
struct CellRun {
  std::unique_ptr<Runtime> rt;
  std::unique_ptr<retain::Manager> mgr;
  retain::StartReport report;
  CellConfig cfg;
  CellRun(const std::string& file, StartMode mode, const std::string& type = "RetainProbe",
          const std::string& save_every = "1h") {
    cfg = parse_cell_config(cell_yaml(file, type, save_every), "test.yaml");
    rt = std::make_unique<Runtime>(cfg);
    mgr = std::make_unique<retain::Manager>(*rt, cfg.retain);
    report = mgr->start(mode);
    rt->start(io::ClockMode::Virtual);
  }
  void scans(int n) {
    for (int i = 0; i < n; ++i) rt->tick();
  }
  std::string stop() {
    rt->finish();
    return mgr->stop();
  }
  std::string value(const std::string& path) {
    const VarInfo* v = rt->vars().find("P." + path);
    return v ? VarRegistry::format(*v) : "<none>";
  }
  std::uint8_t mem(std::size_t byte) { return rt->image().area(io::Area::Memory)[byte]; }
};

// A disk that hangs in every write until release() (test hook on the
// writer thread; bounded: a broken test ends after 30 s instead of hanging).
class StalledDisk {
 public:
  explicit StalledDisk(retain::Writer& w) {
    w.set_before_write([this] {
      std::unique_lock<std::mutex> lock(mu_);
      cv_.wait_for(lock, std::chrono::seconds(30), [this] { return released_; });
    });
  }
  void release() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      released_ = true;
    }
    cv_.notify_all();
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  bool released_ = false;
};

class Retain : public ::testing::Test {
 protected:
  void SetUp() override {
    file_ = plctest::temp_path(::testing::UnitTest::GetInstance()->current_test_info()->name());
    retain::Storage(file_).discard();
  }
  void TearDown() override { retain::Storage(file_).discard(); }
  // Runs a first life of the cell: 10 scans, stop. With save_every 1h the
  // files are sequence 1 (after scan 1: counter 1, in .a) and sequence 2
  // (the stop: counter 10, in .b).
  void first_life() {
    CellRun r(file_, StartMode::Auto);
    r.scans(10);
    r.rt->image().area(io::Area::Memory)[21] = 0x5A;  // a retained %M byte
    ASSERT_EQ(r.stop(), "");
    ASSERT_EQ(r.mgr->stats().written, 2u);
  }
  std::string file_;
};

TEST(RetainDeclarations, ClassesInheritedAndListedInRegistry) {
  auto rt = plctest::make_runtime(
      "tasks: [{name: m, period: 1ms, programs: [P]}]\nprograms: [{name: P, type: RetainProbe}]\n");
  auto cls = [&](const std::string& p) { return rt->vars().find("P." + p)->retain; };
  EXPECT_EQ(cls("counter"), RetainClass::Retain);
  EXPECT_EQ(cls("persist"), RetainClass::Persistent);
  EXPECT_EQ(cls("plain"), RetainClass::None);
  // A whole instance declared RETAIN keeps every field below it.
  EXPECT_EQ(cls("parts.CV"), RetainClass::Retain);
  EXPECT_EQ(cls("parts.cu_prev_"), RetainClass::Retain);
  // Below an unclassed field the block's own declaration counts...
  EXPECT_EQ(cls("own.learned"), RetainClass::Retain);
  EXPECT_EQ(cls("own.scratch"), RetainClass::None);
  // ...below a classed one the instance's class wins.
  EXPECT_EQ(cls("kept.scratch"), RetainClass::Persistent);
  EXPECT_EQ(cls("kept.learned"), RetainClass::Persistent);
  EXPECT_EQ(cls("mem"), RetainClass::Retain);
}

TEST(RetainDeclarations, RetainedOutputIsRefusedWithItsLine) {
  try {
    plctest::make_runtime(
        "tasks: [{name: m, period: 1ms, programs: [P]}]\nprograms: [{name: P, type: "
        "RetainedOutput}]\n");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(e.message.find("P.out: retain located at %QW0: only %M"), std::string::npos)
        << e.what();
    EXPECT_EQ(e.mark.line, 2);
  }
}

TEST(RetainConfig, LocatedErrors) {
  auto err = [](const std::string& retain) {
    try {
      parse_cell_config(
          "image: {memory: 16}\ntasks: [{name: m, period: 1ms, programs: []}]\n" + retain,
          "c.yaml");
    } catch (const ConfigError& e) {
      return e.what() + std::string();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(err("retain: {file: x, save_every: 0ms}"),
            "c.yaml:3:31: key 'save_every': T#0s out of range [T#1ms, T#1h]");
  EXPECT_EQ(err("retain: {save_every: 10ms}"), "c.yaml:3:9: missing key 'file' in retain");
  EXPECT_EQ(err("retain: {file: x, memory: [\"%MB10..%MB16\"]}"),
            "c.yaml:3:28: key 'memory': '%MB10..%MB16' lies outside the %M image (16 bytes; "
            "see image: memory)");
  EXPECT_EQ(err("retain: {file: x, memory: [\"%QB0\"]}"),
            "c.yaml:3:28: key 'memory': %QB0 is not a %M address (only memory is retained)");
  EXPECT_EQ(err("retain: {file: x, every: 1s}"),
            "c.yaml:3:19: unknown key 'every' in retain (expected one of: file, memory, on_damage, "
            "save_every)");
  const CellConfig ok = parse_cell_config(
      "image: {memory: 16}\ntasks: [{name: m, period: 1ms, programs: []}]\nretain: {file: "
      "cell.retain, memory: [\"%MB0..%MB3\", \"%MW10\"]}\n",
      "dir/c.yaml");
  EXPECT_EQ(ok.retain.path, "dir/cell.retain");  // beside the config
  EXPECT_EQ(ok.retain.save_every.value, std::chrono::milliseconds(100));
  ASSERT_EQ(ok.retain.memory.size(), 2u);
  EXPECT_EQ(ok.retain.memory[1].byte, 10u);
  EXPECT_EQ(ok.retain.memory[1].count, 2u);
}

// IEC 61131-3 warm start: RETAIN and PERSISTENT restored, the rest initial.
TEST_F(Retain, WarmStartRestoresRetainAndPersistent) {
  first_life();
  CellRun r(file_, StartMode::Warm);
  EXPECT_EQ(r.report.mode, StartMode::Warm);
  EXPECT_EQ(r.report.sequence, 2u);
  EXPECT_EQ(r.value("counter"), "10");
  EXPECT_EQ(r.value("persist"), "10");
  EXPECT_EQ(r.value("plain"), "0");
  EXPECT_EQ(r.value("label"), "'scanned'");
  EXPECT_EQ(r.value("parts.CV"), "5");
  EXPECT_EQ(r.value("own.learned"), "12.0");
  EXPECT_EQ(r.value("own.scratch"), "1");
  EXPECT_EQ(r.value("kept.scratch"), "11");
  EXPECT_EQ(r.value("mem"), "10");
  EXPECT_EQ(r.mem(21), 0x5A);
  EXPECT_TRUE(r.report.added.empty() && r.report.removed.empty() && r.report.type_changed.empty());
  r.scans(1);
  EXPECT_EQ(r.value("counter"), "11");
  EXPECT_EQ(r.value("mem"), "11");  // the restored %M reached the task's copy
  r.stop();
}

// The manager reads only the global image (ScanHooks::whole_image false):
// a cell with retain copies and merges only its bound bytes, and the
// retained values, bound (P.mem on %MD) and unbound (%MB20..%MB23, written
// from outside), still come back whole.
TEST_F(Retain, ScansCopyOnlyBoundBytesAndKeepEveryRetainedValue) {
  {
    CellRun r(file_, StartMode::Auto);
    r.scans(3);
    EXPECT_FALSE(r.rt->tasks()[0]->whole_image_scan);
    r.rt->image().area(io::Area::Memory)[22] = 0xA5;  // no program is bound to it
    r.scans(3);
    EXPECT_EQ(r.mem(22), 0xA5);
    ASSERT_EQ(r.stop(), "");
  }
  CellRun r(file_, StartMode::Warm);
  EXPECT_EQ(r.value("counter"), "6");
  EXPECT_EQ(r.value("mem"), "6");
  EXPECT_EQ(r.mem(22), 0xA5);
  r.scans(1);
  EXPECT_FALSE(r.rt->tasks()[0]->whole_image_scan);
  EXPECT_EQ(r.value("mem"), "7");  // the restored %M reached the task's copy
  r.stop();
}

TEST_F(Retain, DefaultIsWarmWhenAValidFileExists) {
  first_life();
  CellRun r(file_, StartMode::Auto);
  EXPECT_EQ(r.report.mode, StartMode::Warm);
  EXPECT_EQ(r.value("counter"), "10");
  r.stop();
}

// Cold start: only PERSISTENT kept.
TEST_F(Retain, ColdStartKeepsOnlyPersistent) {
  first_life();
  CellRun r(file_, StartMode::Cold);
  EXPECT_EQ(r.report.mode, StartMode::Cold);
  EXPECT_EQ(r.value("counter"), "0");
  EXPECT_EQ(r.value("label"), "'init'");
  EXPECT_EQ(r.value("parts.CV"), "0");
  EXPECT_EQ(r.value("own.learned"), "2.0");
  EXPECT_EQ(r.mem(21), 0);
  EXPECT_EQ(r.value("persist"), "10");
  EXPECT_EQ(r.value("kept.scratch"), "11");
  EXPECT_EQ(r.value("kept.learned"), "12.0");
  r.stop();
}

// Reset: everything initial, the file removed (also PERSISTENT gone).
TEST_F(Retain, ResetDiscardsTheFile) {
  first_life();
  {
    CellRun r(file_, StartMode::Reset);
    EXPECT_EQ(r.report.mode, StartMode::Reset);
    EXPECT_FALSE(r.report.loaded);
    EXPECT_EQ(r.value("persist"), "0");
    EXPECT_EQ(r.value("counter"), "0");
    EXPECT_FALSE(retain::Storage(file_).load().image);
    r.scans(3);
    r.stop();
  }
  CellRun r(file_, StartMode::Warm);
  EXPECT_EQ(r.value("persist"), "3");  // the new life, numbered from 1 again
  EXPECT_EQ(r.report.sequence, 2u);
  r.stop();
}

// A changed program: matching path + type restored, the rest initial, and
// the report names each (renamed = one removed + one added).
TEST_F(Retain, LayoutChangeRestoresWhatMatchesAndSaysWhatNot) {
  first_life();
  CellRun r(file_, StartMode::Warm, "RetainProbeV2");
  EXPECT_EQ(r.value("count"), "0");    // renamed from counter: initial
  EXPECT_EQ(r.value("persist"), "0");  // DINT -> LINT: initial
  EXPECT_EQ(r.value("extra"), "7");    // added: initial
  EXPECT_EQ(r.value("parts.CV"), "5");
  EXPECT_EQ(r.value("mem"), "10");
  EXPECT_EQ(r.report.added, (std::vector<std::string>{"P.count", "P.extra"}));
  EXPECT_EQ(r.report.type_changed, (std::vector<std::string>{"P.persist (DINT -> LINT)"}));
  EXPECT_EQ(r.report.removed, (std::vector<std::string>{"P.counter", "P.label"}));
  const auto lines = r.report.lines();
  std::string all;
  for (const auto& l : lines) all += l + "\n";
  EXPECT_NE(all.find("not in the file (initial values): P.count, P.extra"), std::string::npos)
      << all;
  EXPECT_NE(all.find("in the file but no longer declared (dropped): P.counter, P.label"),
            std::string::npos)
      << all;
  r.stop();
}

void flip_byte(const std::string& file, long at) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(at < 0 ? at : at, at < 0 ? std::ios::end : std::ios::beg);
  char c = 0;
  f.read(&c, 1);
  f.seekp(at, at < 0 ? std::ios::end : std::ios::beg);
  c = static_cast<char>(c ^ 0x10);
  f.write(&c, 1);
}

// The newest copy damaged: reported, the previous copy used.
TEST_F(Retain, OneCopyCorruptFallsBackToTheOther) {
  first_life();
  flip_byte(file_ + ".b", 60);  // sequence 2, inside the entries
  CellRun r(file_, StartMode::Warm);
  EXPECT_EQ(r.report.mode, StartMode::Warm);
  EXPECT_EQ(r.report.sequence, 1u);
  EXPECT_EQ(r.report.from, file_ + ".a");
  EXPECT_EQ(r.value("counter"), "1");  // the snapshot after the first scan
  ASSERT_EQ(r.report.problems.size(), 1u);
  EXPECT_EQ(r.report.problems[0], file_ + ".b: CRC mismatch (damaged)");
  r.stop();
  // The next save goes to sequence 2 again: over the damaged copy, not over
  // the good one.
  EXPECT_TRUE(retain::Storage(file_).load().problems.empty());
}

TEST_F(Retain, TruncatedFileIsRefused) {
  first_life();
  const std::string b = plctest::read_file(file_ + ".b");
  for (std::size_t keep : {std::size_t(0), std::size_t(20), b.size() / 2, b.size() - 1}) {
    std::ofstream(file_ + ".b", std::ios::binary).write(b.data(), std::streamsize(keep));
    CellRun r(file_, StartMode::Warm);
    EXPECT_EQ(r.report.sequence, 1u) << keep;
    ASSERT_EQ(r.report.problems.size(), 1u) << keep;
    EXPECT_NE(r.report.problems[0].find("cut off"), std::string::npos) << r.report.problems[0];
    r.rt->finish();  // no stop(): keep .b as damaged for the next round
  }
}

TEST_F(Retain, BothCopiesCorruptIsAColdStartWithAReport) {
  first_life();
  flip_byte(file_ + ".a", 30);
  flip_byte(file_ + ".b", -1);  // the CRC itself
  CellRun r(file_, StartMode::Auto);
  EXPECT_FALSE(r.report.loaded);
  EXPECT_EQ(r.report.mode, StartMode::Cold);
  EXPECT_EQ(r.report.problems.size(), 2u);
  EXPECT_EQ(r.value("counter"), "0");
  EXPECT_EQ(r.value("persist"), "0");
  bool said = false;
  for (const auto& l : r.report.lines())
    said |= l.find("no valid copy of the retain file (all damaged)") != std::string::npos;
  EXPECT_TRUE(said);
  r.stop();
}

ssize_t full_disk(int, const void*, std::size_t) {
  errno = ENOSPC;
  return -1;
}

// A full disk: every save fails and is counted; the scans go on; the copy
// written before stays valid and loads.
TEST_F(Retain, FullDiskIsReportedCountedAndKeepsThePreviousCopy) {
  first_life();
  {
    CellRun r(file_, StartMode::Warm, "RetainProbe", "1ms");
    r.mgr->storage().set_write_fn(&full_disk);
    r.scans(200);
    EXPECT_EQ(r.value("counter"), "210");
    const std::string err = r.stop();
    EXPECT_NE(err.find("No space left on device"), std::string::npos) << err;
    const auto st = r.mgr->stats();
    EXPECT_EQ(st.written, 0u);
    EXPECT_GE(st.failed, 2u);  // at least one from the thread, and the final one
    EXPECT_EQ(st.last_error, err);
  }
  CellRun r(file_, StartMode::Warm);
  EXPECT_EQ(r.report.sequence, 2u);
  EXPECT_EQ(r.value("counter"), "10");
  EXPECT_FALSE(std::ifstream(file_ + ".tmp").good());  // no leftover
  r.stop();
}

// A stalled disk never holds up a scan: the writer takes one snapshot and
// hangs in it; every later due snapshot is skipped and counted.
TEST_F(Retain, StalledWriterNeverBlocksTheScan) {
  auto cfg = parse_cell_config(cell_yaml(file_, "RetainProbe", "1ms"), "test.yaml");
  Runtime rt(cfg);
  retain::Manager mgr(rt, cfg.retain);
  StalledDisk disk(mgr.writer());
  mgr.start(StartMode::Cold);
  rt.start(io::ClockMode::Virtual);
  for (int i = 0; i < 1000; ++i) rt.tick();
  EXPECT_EQ(VarRegistry::format(*rt.vars().find("P.counter")), "1000");
  const auto st = mgr.stats();
  EXPECT_EQ(st.offered, 1u);
  EXPECT_EQ(st.skipped, 999u);  // one per period: save_every = 1ms = the task period
  disk.release();
  rt.finish();
  EXPECT_EQ(mgr.stop(), "");
  CellRun r(file_, StartMode::Warm);
  EXPECT_EQ(r.value("counter"), "1000");  // the controlled stop saved the last scan
  r.stop();
}

}  // namespace

namespace {

// plcrun on the filling cell with a retain section: --list-vars shows the
// classes, the second run starts warm, and the options are checked.
TEST(RetainPlcrun, FillingCellListsClassesAndRestartsWarm) {
  const std::string dir = plctest::temp_path("plcrun_retain");
  ASSERT_EQ(std::system(("rm -rf " + dir + " && mkdir -p " + dir).c_str()), 0);
  const std::string cfg = dir + "/cell.yaml";
  std::ofstream(cfg) << plctest::read_file(plctest::source_dir() +
                                           "/programs/filling_cell/cell.yaml")
                     << "\nretain: {file: filling.retain}\n";
  const std::string plcrun = plctest::plcrun_path();
  auto vars = plctest::run_command(plcrun + " " + cfg + " --list-vars");
  ASSERT_EQ(vars.exit_code, 0) << vars.output;
  EXPECT_NE(vars.output.find("Cell.containers DINT retain\n"), std::string::npos);
  EXPECT_NE(vars.output.find("Cell.dose.PreactActual REAL retain\n"), std::string::npos);
  EXPECT_NE(vars.output.find("Cell.dose.prev_reset_ BOOL read-only retain\n"), std::string::npos);
  EXPECT_NE(vars.output.find("Cell.dose.State USINT read-only\n"), std::string::npos);

  auto first =
      plctest::run_command(plcrun + " " + cfg + " --for 60s -q --print-vars Cell.containers");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_NE(first.output.find("plcrun: retain: cold start: no retain file yet"), std::string::npos)
      << first.output;
  auto second =
      plctest::run_command(plcrun + " " + cfg + " --for 1ms -q --print-vars Cell.containers");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_NE(second.output.find("plcrun: retain: warm start from " + dir + "/filling.retain."),
            std::string::npos)
      << second.output;
  // The count of the first life goes on (nonzero: 60 s fill several containers).
  const auto count = [](const std::string& out) {
    const auto at = out.find("Cell.containers = ");
    return at == std::string::npos ? std::string("?")
                                   : out.substr(at + 18, out.find('\n', at) - at - 18);
  };
  EXPECT_EQ(count(second.output), count(first.output));
  EXPECT_NE(count(first.output), "0");
  auto cold = plctest::run_command(plcrun + " " + cfg +
                                   " --cold --for 1ms -q --print-vars Cell.containers");
  EXPECT_EQ(count(cold.output), "0") << cold.output;

  auto both = plctest::run_command(plcrun + " " + cfg + " --cold --warm");
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(
      both.output.find("--warm, --warm-or-cold, --cold and --reset-retain exclude each other"),
      std::string::npos);
  auto none = plctest::run_command(plcrun + " " + plctest::source_dir() +
                                   "/programs/filling_cell/cell.yaml --warm");
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.output.find("the config has no 'retain:' section"), std::string::npos);
  std::system(("rm -rf " + dir).c_str());
}

// Issue 21 follow-up, point 4: a plain --record run that starts warm
// records from the restored values (the learned preact of the dosing, the
// container count); its --replay, which loads no retain file, must start
// from them too - it does, from the state snapshot in the recording's first
// latch (recording.hpp), taken after the restore - and so be bit-exact.
TEST(RetainPlcrun, AWarmStartRecordingReplaysBitExact) {
  const std::string dir = plctest::temp_path("plcrun_retain_record");
  ASSERT_EQ(std::system(("rm -rf " + dir + " && mkdir -p " + dir).c_str()), 0);
  const std::string cfg = dir + "/cell.yaml";
  std::ofstream(cfg) << plctest::read_file(plctest::source_dir() +
                                           "/programs/filling_cell/cell.yaml")
                     << "\nretain: {file: filling.retain}\n";
  const std::string plcrun = plctest::plcrun_path();
  const auto first = plctest::run_command(plcrun + " " + cfg +
                                          " --for 60s -q --print-vars Cell.containers,"
                                          "Cell.dose.PreactActual");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  ASSERT_EQ(first.output.find("Cell.containers = 0\n"), std::string::npos) << first.output;
  const std::string rec = dir + "/warm.plcrec";
  const auto warm = plctest::run_command(plcrun + " " + cfg + " --warm --for 20s -q --record " +
                                         rec + " --print-vars Cell.containers");
  ASSERT_EQ(warm.exit_code, 0) << warm.output;
  ASSERT_NE(warm.output.find("plcrun: retain: warm start from"), std::string::npos) << warm.output;
  const auto replay = plctest::run_command(plcrun + " " + cfg + " --replay " + rec + " -q");
  EXPECT_EQ(replay.exit_code, 0) << replay.output;
  EXPECT_NE(replay.output.find(" 0 with different outputs"), std::string::npos) << replay.output;
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace

namespace {

// A cell with an hmi: section runs as a debugger session; with an HMI alone
// (no console) retain is loaded and saved exactly as in a plain run
// (issue 13: an HMI on a test bench must not turn retain off): the first
// real-time run starts cold and saves, the second starts warm from that
// file, and --cold/--reset-retain are accepted. Bounded: each run ends by
// its --for.
TEST(RetainPlcrun, RealTimeCellWithHmiSectionLoadsAndSavesRetain) {
  const std::string dir = plctest::temp_path("plcrun_retain_hmi");
  ASSERT_EQ(std::system(("rm -rf " + dir + " && mkdir -p " + dir).c_str()), 0);
  const std::string cfg = dir + "/cell.yaml";
  std::ofstream(cfg) << plctest::read_file(plctest::source_dir() +
                                           "/programs/filling_cell/cell.yaml")
                     << "\nretain: {file: filling.retain, save_every: 100ms}\n"
                        "hmi:\n  url: memq://\n  publish: [\"Cell.containers\"]\n";
  const std::string plcrun = plctest::plcrun_path();
  auto first = plctest::run_command(plcrun + " " + cfg + " --realtime --for 1s");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_NE(first.output.find("plcrun: hmi: bridge on memq://"), std::string::npos) << first.output;
  EXPECT_NE(first.output.find("plcrun: retain: cold start: no retain file yet"), std::string::npos)
      << first.output;
  EXPECT_EQ(first.output.find("not loaded or saved"), std::string::npos) << first.output;
  EXPECT_NE(first.output.find(" failed\n"), std::string::npos)
      << first.output;  // the writer's line
  EXPECT_EQ(first.output.find("FAILED"), std::string::npos) << first.output;
  auto second = plctest::run_command(plcrun + " " + cfg + " --realtime --for 100ms");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_NE(second.output.find("plcrun: retain: warm start from " + dir + "/filling.retain."),
            std::string::npos)
      << second.output;
  auto cold = plctest::run_command(plcrun + " " + cfg + " --realtime --cold --for 100ms");
  EXPECT_EQ(cold.exit_code, 0) << cold.output;
  EXPECT_NE(cold.output.find("plcrun: retain: cold start"), std::string::npos) << cold.output;
  // A console session in virtual time keeps its rule: it may goto/restart,
  // so no retain.
  auto debug = plctest::run_command(plcrun + " " + cfg + " --warm --commands /dev/null");
  EXPECT_EQ(debug.exit_code, 2) << debug.output;
  // In real time the debugger never rebuilds the cell (goto and restart are
  // refused): the session loads and saves as a plain run does (issue 21,
  // online change of retained programs), also when it ends by its file.
  std::ofstream(dir + "/cmds") << "continue for 50ms\nquit\n";
  auto rt_debug =
      plctest::run_command(plcrun + " " + cfg + " --realtime --warm --commands " + dir + "/cmds");
  EXPECT_EQ(rt_debug.exit_code, 0) << rt_debug.output;
  EXPECT_NE(rt_debug.output.find("plcrun: retain: warm start from " + dir + "/filling.retain."),
            std::string::npos)
      << rt_debug.output;
  EXPECT_NE(rt_debug.output.find(" saves (last sequence "), std::string::npos) << rt_debug.output;
  EXPECT_EQ(rt_debug.output.find("FAILED"), std::string::npos) << rt_debug.output;
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace

namespace {

// The debugger's restart (virtual time): warm keeps RETAIN and PERSISTENT
// values of the running cell, cold only PERSISTENT (IEC 61131-3 6.5.6).
TEST(RetainDebugger, RestartWarmAndCold) {
  const auto cfg = parse_cell_config(
      "image: {memory: 16}\ntasks: [{name: m, period: 1ms, programs: [P]}]\n"
      "programs: [{name: P, type: RetainProbe}]\n",
      "test.yaml");
  debug::Debugger::Options o;
  debug::Debugger d([&cfg] { return std::make_unique<Runtime>(cfg); }, o);
  d.execute("step 10");
  EXPECT_EQ(d.execute("print P.counter P.persist P.plain"),
            "P.counter = 10  (DINT)\nP.persist = 10  (DINT)\nP.plain = 10  (DINT)\n");
  const std::string warm = d.execute("restart warm");
  EXPECT_NE(warm.find("warm restart: 13 RETAIN/PERSISTENT values kept"), std::string::npos) << warm;
  EXPECT_EQ(d.execute("print P.counter P.persist P.plain P.mem"),
            "P.counter = 10  (DINT)\nP.persist = 10  (DINT)\nP.plain = 0  (DINT)\nP.mem = 10  "
            "(DINT %MD8)\n");
  d.execute("step 5");
  const std::string cold = d.execute("restart cold");
  EXPECT_NE(cold.find("cold restart: 3 PERSISTENT values kept"), std::string::npos) << cold;
  EXPECT_EQ(d.execute("print P.counter P.persist P.kept.scratch"),
            "P.counter = 0  (DINT)\nP.persist = 15  (DINT)\nP.kept.scratch = 16  (DINT)\n");
  EXPECT_EQ(d.execute("restart hot"), "usage: restart warm|cold\n");
}

}  // namespace

namespace {

// Two tasks: a snapshot is complete when each task has copied its part at
// the end of one of its own scans; only then does it go to the writer.
TEST(RetainTasks, SnapshotGathersOneScanOfEveryTask) {
  const std::string file = plctest::temp_path("two_tasks");
  retain::Storage(file).discard();
  const auto cfg = parse_cell_config(
      "image: {memory: 16}\ntasks: [{name: fast, period: 1ms, programs: [A]}, {name: slow, "
      "period: 2ms, programs: [B]}]\nprograms: [{name: A, type: RetainProbe}, {name: B, type: "
      "RetainProbe, bind: {mem: \"%MD4\"}}]\nretain: {file: " +
          file + ", save_every: 2ms}\n",
      "test.yaml");
  Runtime rt(cfg);
  retain::Manager mgr(rt, cfg.retain);
  StalledDisk disk(mgr.writer());
  mgr.start(StartMode::Cold);
  rt.start(io::ClockMode::Virtual);
  for (int i = 0; i < 100; ++i) rt.tick();  // t = 0 .. 99 ms
  const auto st = mgr.stats();
  EXPECT_EQ(st.offered, 1u);   // complete at t = 0 (both tasks scanned)
  EXPECT_EQ(st.skipped, 49u);  // t = 2, 4, ... 98
  disk.release();
  rt.finish();
  EXPECT_EQ(mgr.stop(), "");
  Runtime again(cfg);
  retain::Manager m2(again, cfg.retain);
  m2.start(StartMode::Warm);
  EXPECT_EQ(VarRegistry::format(*again.vars().find("A.counter")), "100");
  EXPECT_EQ(VarRegistry::format(*again.vars().find("B.counter")), "50");
  m2.stop();
  retain::Storage(file).discard();
}

}  // namespace

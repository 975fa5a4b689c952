// Recording and replay (issue 10): real-time recordings of several tasks
// replay bit-exact (the order of the tasks' image-locked halves is part of
// the recording), and the file format (PLCREC04, recording.hpp) refuses any
// damage with an error that names the scan.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <thread>

#include "debugger_deadline.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/debug/recording.hpp"
#include "plc/io/located.hpp"
#include "plc/program.hpp"
#include "plc_test_paths.hpp"
#include "test_helpers.hpp"
#include "test_programs.hpp"

using namespace plc;

namespace {

// Two of these in two tasks pass a value back and forth through %M: what
// one task's latch copies depends on whether the other has merged yet.
class Relay : public ProgramBase<Relay> {
 public:
  io::Located<DINT> in{"%MD0"};
  io::Located<DINT> out{"%MD4"};
  DINT k = 1;
  void cycle(const ScanContext& ctx) override {
    out = static_cast<DINT>(static_cast<std::uint32_t>(in) * 3U + static_cast<std::uint32_t>(k) +
                            static_cast<std::uint32_t>(ctx.now.count() / 1'000'000));
    ++k;
  }
  PLC_REFLECT(in, out, k)
};
PLC_REGISTER_PROGRAM(Relay)

const char* kRelayCell = R"(
tasks:
  - {name: a, period: 1ms, programs: [A]}
  - {name: b, period: 2ms, programs: [B]}
programs:
  - {name: A, type: Relay}
  - {name: B, type: Relay, bind: {in: "%MD4", out: "%MD0"}}
)";

std::string demo_path() { return plctest::source_path("programs/demo/cell.yaml"); }

bool has(const std::string& s, const std::string& what) {
  return s.find(what) != std::string::npos;
}

std::vector<std::uint8_t> read_bytes(const std::string& path) {
  const std::string s = plctest::read_file(path);
  return {s.begin(), s.end()};
}

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& b) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

std::uint16_t le16(const std::vector<std::uint8_t>& b, std::size_t at) {
  return std::uint16_t(b[at] | b[at + 1] << 8);
}

std::uint32_t le32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
         std::uint32_t(b[at + 3]) << 24;
}

void put_le(std::vector<std::uint8_t>& b, std::size_t at, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) b[at + std::size_t(i)] = std::uint8_t(v >> (8 * i));
}

// CRC-32 as zlib's crc32(prev, data), written from the definition
// (reflected polynomial 0xEDB88320): the outside reference for the file's
// CRCs, independent of the Boost CRC the runtime uses.
std::uint32_t zlib_crc32(const std::uint8_t* p, std::size_t n, std::uint32_t prev = 0) {
  std::uint32_t c = ~prev;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320U & (0U - (c & 1U)));
  }
  return ~c;
}

struct Frame {
  std::size_t at;  // offset of the type byte
  char type;
  std::uint32_t len;
};

// The records of a file, walked by the format's framing (8-byte magic,
// then u8 type, u32 length, payload, u32 CRC).
std::vector<Frame> frames(const std::vector<std::uint8_t>& b) {
  std::vector<Frame> out;
  for (std::size_t at = 8; at + 5 <= b.size();) {
    const std::uint32_t len = le32(b, at + 1);
    out.push_back({at, char(b[at]), len});
    at += 9 + len;
  }
  return out;
}

// Recomputes every record's running CRC (after a test changed a payload).
void reseal(std::vector<std::uint8_t>& b) {
  std::uint32_t crc = 0;
  for (const Frame& f : frames(b)) {
    crc = zlib_crc32(b.data() + f.at, 5 + f.len, crc);
    put_le(b, f.at + 5 + f.len, crc, 4);
  }
}

// A virtual-time recording of the demo cell (two tasks, one device).
std::vector<std::uint8_t> record_demo(const std::string& path, std::chrono::milliseconds span) {
  auto rt = std::make_unique<Runtime>(load_cell_config(demo_path()));
  {
    debug::Recorder r(*rt, path);
    rt->run(io::ClockMode::Virtual, span);
    EXPECT_EQ(r.close(), "");
  }
  return read_bytes(path);
}

// The error a replay of `bytes` stops with ("" if it is accepted).
std::string replay_error(const std::vector<std::uint8_t>& bytes) {
  const std::string path = plctest::temp_path("damaged.rec");
  write_bytes(path, bytes);
  Runtime rt(load_cell_config(demo_path()));
  try {
    debug::Replayer r(rt, path);
  } catch (const debug::RecordingError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("not a RecordingError: ") + e.what();
  }
  return "";
}

std::size_t scan_of(const std::vector<Frame>& fs, std::size_t byte) {
  std::size_t scans = 0;
  for (const Frame& f : fs) {
    if (byte < f.at + 9 + f.len) break;
    scans += f.type == 'M';
  }
  return scans;
}

}  // namespace

// ---------------------------------------------------------------- point 1

// Halves driven apart in virtual time (as a replay and the test below do),
// with no hook that asks for whole-image scans: A latches, B runs a whole
// scan and writes %MD0, then A merges. A is bound to %MD0 (it reads it), so
// copying A's bound bytes back, as a back-to-back virtual scan may, would
// put A's stale %MD0 over B's; the merge takes only the bits A changed.
TEST(RealTimeRecording, SplitHalvesMergeOnlyTheBitsTheScanChanged) {
  auto rt = plctest::make_runtime(kRelayCell);
  TaskRuntime& a = *rt->tasks()[0];
  TaskRuntime& b = *rt->tasks()[1];
  const ScanContext ca = rt->latch_scan(a, TIME(0));
  EXPECT_FALSE(a.whole_image_scan);
  rt->finish_scan(b, rt->latch_scan(b, TIME(0)));
  rt->finish_scan(a, ca);
  const auto global = rt->image().area(io::Area::Memory);
  const auto from_b = b.image.area(io::Area::Memory);
  ASSERT_NE(from_b[0] | from_b[1] | from_b[2] | from_b[3], 0) << "B wrote nothing to %MD0";
  EXPECT_TRUE(std::equal(from_b.begin(), from_b.begin() + 4, global.begin()))
      << "A's merge put its stale %MD0 over B's";
  const auto from_a = a.image.area(io::Area::Memory);
  EXPECT_TRUE(std::equal(from_a.begin() + 4, from_a.begin() + 8, global.begin() + 4));
}

// The recorder reads only the global image: recorded scans copy and merge
// their bound bytes, as unrecorded ones do (no whole-image copy per scan).
TEST(RealTimeRecording, RecordedScansCopyOnlyTheirBoundBytes) {
  const std::string rec = plctest::temp_path("bound.rec");
  auto rt = plctest::make_runtime(kRelayCell);
  debug::Recorder recorder(*rt, rec);
  TaskRuntime& a = *rt->tasks()[0];
  rt->finish_scan(a, rt->latch_scan(a, TIME(0)));
  EXPECT_FALSE(a.whole_image_scan);
  EXPECT_EQ(recorder.close(), "");
  std::remove(rec.c_str());
}

// Two tasks exchanging data through %M, their scans' halves interleaved in
// many orders (as real-time threads do): the recording replays with
// identical outputs and lands on the same program state. Driven phase by
// phase from one thread, so the interleavings are forced, not timed.
TEST(RealTimeRecording, InterleavedScansOfTwoTasksReplayExactly) {
  const std::string rec = plctest::temp_path("interleaved.rec");
  auto rt = plctest::make_runtime(kRelayCell);
  TaskRuntime& a = *rt->tasks()[0];
  TaskRuntime& b = *rt->tasks()[1];
  std::uint64_t recorded = 0;
  std::vector<std::pair<int, TIME>> latch_order;
  {
    debug::Recorder recorder(*rt, rec);
    ScanContext ctx[2];
    bool latched[2] = {false, false};
    latch_order.reserve(4000);
    std::int64_t k[2] = {0, 0};
    std::uint32_t x = 2463534242U;  // xorshift32, fixed seed
    for (int i = 0; i < 4000; ++i) {
      x ^= x << 13;
      x ^= x >> 17;
      x ^= x << 5;
      const int n = int(x & 1U);
      TaskRuntime& t = n == 0 ? a : b;
      if (!latched[n]) {
        latch_order.emplace_back(n, t.period * k[n]);
        ctx[n] = rt->latch_scan(t, t.period * k[n]++);
      } else {
        rt->finish_scan(t, ctx[n]);
      }
      latched[n] = !latched[n];
    }
    for (int n = 0; n < 2; ++n)
      if (latched[n]) rt->finish_scan(n == 0 ? a : b, ctx[n]);
    EXPECT_EQ(recorder.close(), "");
    recorded = recorder.scans();
  }
  const auto* ra = static_cast<Relay*>(rt->program("A"));
  const auto* rb = static_cast<Relay*>(rt->program("B"));
  const auto final_a = ra->k, final_out = DINT(ra->out), final_in = DINT(ra->in);
  ASSERT_GT(recorded, 1900u);

  auto replay_rt = plctest::make_runtime(kRelayCell);
  debug::Replayer replay(*replay_rt, rec);
  while (replay.step()) {
  }
  EXPECT_EQ(replay.error(), "");
  EXPECT_EQ(replay.scans(), recorded);
  EXPECT_EQ(replay.mismatches(), 0u) << "first at scan " << replay.first_mismatch();
  const auto* pa = static_cast<Relay*>(replay_rt->program("A"));
  EXPECT_EQ(pa->k, final_a);
  EXPECT_EQ(DINT(pa->out), final_out);
  EXPECT_EQ(DINT(pa->in), final_in);
  EXPECT_EQ(static_cast<Relay*>(replay_rt->program("B"))->k, rb->k);

  // The interleaving matters: the same scans at the same times, each run
  // whole in the order they latched (what a replay that ignores the order
  // of the halves does), end elsewhere.
  auto seq = plctest::make_runtime(kRelayCell);
  for (const auto& [n, now] : latch_order) {
    TaskRuntime& t = *seq->tasks()[std::size_t(n)];
    seq->finish_scan(t, seq->latch_scan(t, now));
  }
  EXPECT_NE(DINT(static_cast<Relay*>(seq->program("A"))->out), final_out);

  // The same file with each merge moved up to its latch (the scans kept,
  // the order of their halves lost) replays with differences.
  const auto file = read_bytes(rec);
  const auto fs = frames(file);
  std::vector<std::uint8_t> moved(file.begin(), file.begin() + std::ptrdiff_t(fs[1].at));
  std::vector<bool> used(fs.size());
  auto append = [&](const Frame& f) {
    moved.insert(moved.end(), file.begin() + std::ptrdiff_t(f.at),
                 file.begin() + std::ptrdiff_t(f.at + 9 + f.len));
  };
  for (std::size_t i = 1; i + 1 < fs.size(); ++i) {
    if (fs[i].type != 'L') continue;
    append(fs[i]);
    for (std::size_t j = i + 1; j + 1 < fs.size(); ++j)
      if (fs[j].type == 'M' && !used[j] && le16(file, fs[j].at + 5) == le16(file, fs[i].at + 5)) {
        used[j] = true;
        append(fs[j]);
        break;
      }
  }
  append(fs.back());
  reseal(moved);
  write_bytes(rec, moved);
  auto moved_rt = plctest::make_runtime(kRelayCell);
  debug::Replayer moved_replay(*moved_rt, rec);
  while (moved_replay.step()) {
  }
  EXPECT_EQ(moved_replay.scans(), recorded);
  EXPECT_GT(moved_replay.mismatches(), 0u);
  std::remove(rec.c_str());
}

namespace {

// Records a cell in real time through the debugger, with breakpoints (the
// logic pauses), steps, forces and writes in between, then replays it.
// Runs real time because that is what it checks, yet asserts nothing about
// timing: it must pass on a loaded 2-core machine without SCHED_FIFO. So
// the tasks run without their watchdogs (the demo's fast task has 10 ms,
// which a preempted first scan overran once under ctest -j2, stopping the
// task and every "run until" with it); ATaskStoppedByItsWatchdogReplays
// covers a recorded watchdog stop.
void record_real_time_and_replay(CellConfig cfg, const std::vector<std::string>& commands,
                                 const std::string& rec) {
  for (TaskConfig& t : cfg.tasks) t.watchdog.value = 0;
  std::string stopped;
  {
    debug::Debugger::Options o;
    o.mode = io::ClockMode::RealTime;
    o.span = std::chrono::minutes(1);
    debug::Debugger d([cfg] { return std::make_unique<Runtime>(cfg); }, o);
    plctest::Deadline deadline(d);
    EXPECT_TRUE(has(d.execute("record " + rec), "recording every scan's inputs"));
    for (const std::string& c : commands) {
      const std::string out = d.execute(c);
      EXPECT_FALSE(has(out, "unknown") || has(out, "usage")) << c << ": " << out;
      if (c.rfind("run until", 0) == 0) {
        EXPECT_TRUE(has(out, "holds")) << c << ": " << out;
      }
    }
    stopped = d.execute("record stop");
    d.execute("quit");
  }
  ASSERT_TRUE(has(stopped, "recording stopped, ")) << stopped;
  const std::string scans = stopped.substr(stopped.find(", ") + 2);
  debug::Debugger::Options o;
  o.replay_file = rec;
  o.span = std::chrono::hours(1);
  debug::Debugger r([cfg] { return std::make_unique<Runtime>(cfg); }, o);
  const std::string out = r.execute("continue");
  EXPECT_TRUE(has(out, "the recording has ended")) << out;
  EXPECT_TRUE(
      has(out, "replay " + scans.substr(0, scans.find(' ')) + " scans, 0 output mismatch(es)"))
      << "recorded: " << stopped << out;
  EXPECT_FALSE(has(out, "diverged")) << out;
  // goto backwards in the replay lands on the same state again.
  r.execute("goto 200");
  const std::string at200 = r.execute("print %QW0 %MD4");
  r.execute("goto 100");
  EXPECT_TRUE(has(r.execute("goto 200"), "at scan 200"));
  EXPECT_EQ(r.execute("print %QW0 %MD4"), at200);
  std::remove(rec.c_str());
}

}  // namespace

// The demo cell (two tasks sharing %M) in real time, with a breakpoint, a
// step, forces on program variables, an input and an output, a write and
// an unforce-restore while recording.
TEST(RealTimeRecording, DemoCellWithPausesAndForcesReplaysBitExact) {
  record_real_time_and_replay(
      load_cell_config(demo_path()),
      {"force Tank.high_level 3000", "force Tank.hold_time T#200ms", "force %IX3.7 TRUE",
       "run until Tank.step = 2", "step 3", "force %QX2.5 TRUE", "write Tank.low_level 2500",
       "run until Tank.step = 3", "unforce all restore", "run until Tank.step = 1"},
      plctest::temp_path("rt_demo.rec"));
}

// plcrun --realtime --record on the two-task demo cell: both task threads
// record at once (this crashed: they shared one buffer), and the replay has
// no difference. Without the watchdogs (the test asserts nothing about
// timing: a scan stalled past 10 ms on a loaded machine stopped the task,
// and plcrun exits 1 then).
TEST(RealTimeRecording, PlcrunRecordsTheTwoTaskDemoInRealTimeAndReplaysIt) {
  const std::string rec = plctest::temp_path("rt_cli.rec");
  const std::string cell = plctest::demo_without_watchdogs("rt_cli_demo.yaml");
  ASSERT_FALSE(cell.empty()) << "programs/demo/cell.yaml changed";
  auto r = plctest::run_command(plctest::plcrun_path() + " " + cell +
                                " --realtime --for 1500ms -q --record " + rec);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::size_t at = r.output.find("recorded ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const std::string scans = r.output.substr(at + 9, r.output.find(' ', at + 9) - at - 9);
  EXPECT_GT(std::stoul(scans), 1000u) << r.output;
  r = plctest::run_command(plctest::plcrun_path() + " " + cell + " -q --replay " + rec);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "replay: " + scans + " scans, 0 with different outputs")) << r.output;
  std::remove(rec.c_str());
  std::remove(cell.c_str());
}

// Virtual time: writes and forces made at a freeze point and on program
// variables and outputs are recorded too, and the recording is the same
// file every time.
TEST(Recording, ForcesAndFreezePointWritesReplayAndTheFileIsDeterministic) {
  std::string files[2];
  for (int i = 0; i < 2; ++i) {
    const std::string rec = plctest::temp_path("freeze" + std::to_string(i) + ".rec");
    {
      const CellConfig cfg = load_cell_config(demo_path());
      debug::Debugger::Options o;
      o.span = std::chrono::minutes(1);
      debug::Debugger d([cfg] { return std::make_unique<Runtime>(cfg); }, o);
      std::vector<std::string> script = {"write Tank.step 3", "step"};
      std::size_t next = 0;
      d.set_io(
          [&](const std::string&) -> std::optional<std::string> {
            return next < script.size() ? std::optional(script[next++]) : std::nullopt;
          },
          [](const std::string&) {});
      d.execute("record " + rec);
      d.execute("force Tank.high_level 3000");
      d.execute("force %QW4 16#1234");
      d.execute("continue for 1500ms");
      d.execute("break before Tank if Tank.step = 2");
      const std::string frozen = d.execute("continue");
      EXPECT_TRUE(has(frozen, "stepped from the freeze point")) << frozen;
      d.execute("delete all");
      d.execute("unforce Tank.high_level restore");
      d.execute("continue for 1s");
      EXPECT_TRUE(has(d.execute("record stop"), "recording stopped"));
    }
    files[i] = plctest::read_file(rec);
    debug::Debugger::Options o;
    o.replay_file = rec;
    const CellConfig cfg = load_cell_config(demo_path());
    debug::Debugger r([cfg] { return std::make_unique<Runtime>(cfg); }, o);
    const std::string out = r.execute("continue");
    EXPECT_TRUE(has(out, " 0 output mismatch(es)")) << out;
    EXPECT_TRUE(has(r.execute("print Tank.high_level"), "= 22000")) << "the restore replayed";
  }
  EXPECT_GT(files[0].size(), 1000u);
  EXPECT_EQ(files[0], files[1]);
}

// The recorder compares, at a scan's merge, only the words of %Q and %M
// that scan can have changed: its task's bound bytes and the words the
// debugger wrote (recording.hpp). Writes and forces of bytes no program is
// bound to, made well after the recording's first (whole) comparison, must
// still reach the output hash: the replay, which hashes its whole image,
// finds no difference, and the forced and written bytes replay.
TEST(Recording, WritesAndForcesOfUnboundImageBytesReachTheOutputHash) {
  const std::string rec = plctest::temp_path("unbound.rec");
  const CellConfig cfg = load_cell_config(demo_path());
  {
    debug::Debugger::Options o;
    o.span = std::chrono::minutes(1);
    debug::Debugger d([cfg] { return std::make_unique<Runtime>(cfg); }, o);
    d.execute("record " + rec);
    d.execute("continue for 100ms");
    d.execute("write %MW100 16#1234");  // %M no program is bound to
    d.execute("step");
    d.execute("force %QB10 16#5A");  // %Q no program is bound to
    d.execute("force %MB37 16#A5");
    d.execute("continue for 50ms");
    d.execute("unforce %QB10");
    d.execute("continue for 20ms");
    d.execute("write %QW12 16#BEEF");
    d.execute("write %MD252 7");  // the last word of %M
    d.execute("step 3");
    EXPECT_TRUE(has(d.execute("record stop"), "recording stopped"));
  }
  debug::Debugger::Options o;
  o.replay_file = rec;
  debug::Debugger r([cfg] { return std::make_unique<Runtime>(cfg); }, o);
  const std::string out = r.execute("continue");
  EXPECT_TRUE(has(out, " 0 output mismatch(es)")) << out;
  EXPECT_TRUE(has(r.execute("print %MW100"), "16#1234")) << r.execute("print %MW100");
  EXPECT_TRUE(has(r.execute("print %MB37"), "16#A5")) << r.execute("print %MB37");
  EXPECT_TRUE(has(r.execute("print %QW12"), "16#BEEF")) << r.execute("print %QW12");
  std::remove(rec.c_str());
}

namespace {

// Records `commands` in a debugger session on `yaml`, replays the recording,
// and returns the replay's stop report.
std::string record_and_replay(const std::string& yaml, io::ClockMode mode,
                              const std::vector<std::string>& commands, const std::string& rec) {
  const CellConfig cfg = parse_cell_config(yaml, "stop.yaml");
  {
    debug::Debugger::Options o;
    o.mode = mode;
    o.span = std::chrono::minutes(1);
    debug::Debugger d([cfg] { return std::make_unique<Runtime>(cfg); }, o);
    plctest::Deadline deadline(d);
    d.execute("record " + rec);
    for (const std::string& c : commands) d.execute(c);
    EXPECT_TRUE(has(d.execute("record stop"), "recording stopped"));
    d.execute("quit");
  }
  debug::Debugger::Options o;
  o.replay_file = rec;
  debug::Debugger r([cfg] { return std::make_unique<Runtime>(cfg); }, o);
  std::string out = r.execute("continue");
  out += r.execute("stats");
  std::remove(rec.c_str());
  return out;
}

}  // namespace

// A task stopped by an exception (virtual time) or by its watchdog (real
// time, from the watchdog thread) while recording: its safe outputs go
// into the image at the recorded point of the replay too.
TEST(Recording, ATaskStoppedByAFaultReplays) {
  const std::string out =
      record_and_replay(R"(
tasks:
  - {name: main, period: 1ms, programs: [T]}
  - {name: other, period: 2ms, programs: [L]}
programs:
  - {name: T, type: Thrower}
  - {name: L, type: LoopCounter}
)",
                        io::ClockMode::Virtual, {"step 50", "write T.fire TRUE", "step 100"},
                        plctest::temp_path("fault.rec"));
  EXPECT_TRUE(has(out, " 0 output mismatch(es)")) << out;
  EXPECT_TRUE(has(out, "STOPPED")) << out;
  EXPECT_FALSE(has(out, "diverged")) << out;
}

TEST(RealTimeRecording, ATaskStoppedByItsWatchdogReplays) {
  const std::string out =
      record_and_replay(R"(
tasks:
  - {name: main, period: 1ms, watchdog: 10, programs: [S]}
  - {name: other, period: 2ms, programs: [L]}
programs:
  - {name: S, type: Spinner}
  - {name: L, type: LoopCounter, bind: {to_dev: "%QD8", from_dev: "%ID8"}}
)",
                        io::ClockMode::RealTime,
                        {"run until L.count > 100", "write S.spin TRUE", "run until L.count > 300"},
                        plctest::temp_path("watchdog.rec"));
  EXPECT_TRUE(has(out, " 0 output mismatch(es)")) << out;
  EXPECT_TRUE(has(out, "STOPPED: stopped in the recording (watchdog")) << out;
  EXPECT_FALSE(has(out, "diverged")) << out;
}

// ---------------------------------------------------------------- point 3

// The outside reference: every record's stored CRC is zlib's crc32
// continued over the records (CRC catalogue check value first).
TEST(RecordingFormat, EveryRecordCarriesTheRunningZlibCrc32) {
  const std::uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  ASSERT_EQ(zlib_crc32(check, 9), 0xCBF43926U);                            // CRC-32 check value
  ASSERT_EQ(zlib_crc32(check + 3, 6, zlib_crc32(check, 3)), 0xCBF43926U);  // continued
  const auto b = record_demo(plctest::temp_path("crc.rec"), std::chrono::milliseconds(50));
  ASSERT_EQ(std::string(b.begin(), b.begin() + 8), "PLCREC05");
  const auto fs = frames(b);
  ASSERT_GT(fs.size(), 100u);
  EXPECT_EQ(fs.front().type, 'H');
  EXPECT_EQ(fs.back().type, 'E');
  EXPECT_EQ(fs.back().at + 9 + fs.back().len, b.size());
  std::uint32_t crc = 0;
  for (const Frame& f : fs) {
    crc = zlib_crc32(b.data() + f.at, 5 + f.len, crc);
    ASSERT_EQ(le32(b, f.at + 5 + f.len), crc) << "record at " << f.at;
  }
  // E: u64 scans (55 = 50 of the 1 ms task + 5 of the 10 ms task), u64
  // records before it (header, a latch and a merge per scan).
  const std::size_t e = fs.back().at + 5;
  EXPECT_EQ(le32(b, e), 55u);
  EXPECT_EQ(le32(b, e + 8), 1u + 2u * 55u);
}

// 200 single-bit flips anywhere in the file: every one is refused with an
// error that names the scan of the damaged record (before: about half
// replayed with exit code 0).
TEST(RecordingDamage, EverySingleBitFlipIsRefusedNamingTheScan) {
  const auto good = record_demo(plctest::temp_path("flip.rec"), std::chrono::milliseconds(300));
  ASSERT_EQ(replay_error(good), "");
  const auto fs = frames(good);
  std::uint32_t x = 88172645U;
  for (int i = 0; i < 200; ++i) {
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    const std::size_t byte = x % good.size();
    auto bad = good;
    bad[byte] ^= std::uint8_t(1U << ((x >> 24) % 8));
    const std::string err = replay_error(bad);
    ASSERT_FALSE(err.empty()) << "flip in byte " << byte << " went unnoticed";
    if (byte < 8) {
      EXPECT_TRUE(has(err, "not a recording") || has(err, "not supported")) << err;
    } else {
      EXPECT_TRUE(has(err, "at scan " + std::to_string(scan_of(fs, byte)) + " "))
          << "byte " << byte << ": " << err;
    }
  }
}

TEST(RecordingDamage, PlcrunReplayExitsWithOneAndNamesTheScan) {
  const std::string rec = plctest::temp_path("cli_flip.rec");
  auto b = record_demo(rec, std::chrono::milliseconds(300));
  const auto fs = frames(b);
  const Frame& f = fs[fs.size() / 2];
  b[f.at + 5 + f.len / 2] ^= 0x10;
  write_bytes(rec, b);
  const auto r =
      plctest::run_command(plctest::plcrun_path() + " " + demo_path() + " -q --replay " + rec);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "recording damaged at scan " + std::to_string(scan_of(fs, f.at)) +
                                " (byte offset " + std::to_string(f.at) + "): CRC mismatch"))
      << r.output;
  std::remove(rec.c_str());
}

// A file cut at any record boundary (between scans, between a latch and its
// merge, before the end record) or inside a record is incomplete.
TEST(RecordingDamage, AFileCutAnywhereIsIncomplete) {
  const auto good = record_demo(plctest::temp_path("cut.rec"), std::chrono::milliseconds(100));
  const auto fs = frames(good);
  for (const Frame& f : fs) {
    for (std::size_t cut : {f.at, f.at + 3, f.at + 9 + f.len / 2}) {
      if (cut >= good.size()) continue;
      const auto c = debug::check_recording({good.data(), cut});
      EXPECT_TRUE(!c.ok && has(c.error, "incomplete")) << "cut at " << cut << ": " << c.error;
    }
  }
  // What plcrun --replay does with it: the same (cut before the end record,
  // and between a latch and its merge).
  EXPECT_TRUE(has(replay_error({good.begin(), good.begin() + std::ptrdiff_t(fs.back().at)}),
                  "recording incomplete: it ends after scan"));
  EXPECT_TRUE(has(replay_error({good.begin(), good.begin() + std::ptrdiff_t(fs[3].at)}),
                  "recording incomplete"));
}

// A damaged length is refused before anything is allocated for it; times,
// states and lengths are checked even when the CRC is right (a crafted or
// buggy file).
TEST(RecordingDamage, LengthsTimesAndStatesAreCheckedBeforeUse) {
  const auto good = record_demo(plctest::temp_path("crafted.rec"), std::chrono::milliseconds(50));
  const auto fs = frames(good);
  std::size_t latch = 0, merge = 0, pair = 0;  // a later latch, a merge, a latch+merge pair
  for (std::size_t i = 3; i + 1 < fs.size(); ++i) {
    if (!latch && fs[i].type == 'L') latch = fs[i].at;
    if (!merge && fs[i].type == 'M') merge = fs[i].at;
    if (!pair && fs[i].type == 'L' && fs[i + 1].type == 'M') pair = i;
  }
  ASSERT_TRUE(latch && merge && pair);

  auto bad = good;
  put_le(bad, merge + 1, 0xFFFFFFF0U, 4);  // a 4 GB record
  EXPECT_TRUE(has(replay_error(bad), "exceeds the limit")) << replay_error(bad);
  bad = good;
  put_le(bad, merge + 1, 1U << 20, 4);  // 1 MB: more than the file
  EXPECT_TRUE(has(replay_error(bad), "runs past the end of the file")) << replay_error(bad);

  // Latch payload: u16 task, u64 cycle, i64 time ns, inputs, u16 devices,
  // u8 states.
  const std::size_t time = latch + 5 + 2 + 8;
  for (std::int64_t t : {std::int64_t(INT64_MAX), std::int64_t(-1000000)}) {
    bad = good;
    put_le(bad, time, std::uint64_t(t), 8);
    reseal(bad);
    EXPECT_TRUE(has(replay_error(bad), "out of range")) << t << ": " << replay_error(bad);
  }
  bad = good;
  put_le(bad, time, le32(good, time) + 1, 4);  // off the 1 ms grid
  reseal(bad);
  EXPECT_TRUE(has(replay_error(bad), "period grid")) << replay_error(bad);
  const bool fast = le16(good, latch + 5) == 0;  // task 0 exchanges the tank's 4 input bytes
  const std::size_t state = time + 8 + (fast ? 4 : 0) + 2;
  bad = good;
  bad[state] = 9;
  reseal(bad);
  EXPECT_TRUE(has(replay_error(bad), "device state 9 out of range")) << replay_error(bad);

  // A lost scan (its latch and merge cut out, the CRCs made right again):
  // the end record's count and the task's cycle count both disagree.
  bad.assign(good.begin(), good.begin() + std::ptrdiff_t(fs[pair].at));
  bad.insert(bad.end(), good.begin() + std::ptrdiff_t(fs[pair + 2].at), good.end());
  reseal(bad);
  EXPECT_TRUE(has(replay_error(bad), "recording damaged at scan")) << replay_error(bad);
}

TEST(RecordingDamage, AnOldFormatIsRefusedWithItsVersion) {
  std::vector<std::uint8_t> old = {'P', 'L', 'C', 'R', 'E', 'C', '0', '4'};
  old.resize(64, 0);
  const std::string err = replay_error(old);
  EXPECT_TRUE(has(err, "PLCREC04 is not supported: this plcrun reads PLCREC05")) << err;
  EXPECT_TRUE(has(replay_error({'x', 'y'}), "not a recording"));
}

// The reader's entry point for fuzzing and tools: a buffer in, the first
// damage out, no Runtime needed.
TEST(RecordingDamage, CheckRecordingReadsABufferWithoutARuntime) {
  const auto good = record_demo(plctest::temp_path("check.rec"), std::chrono::milliseconds(20));
  const auto ok = debug::check_recording(good);
  EXPECT_TRUE(ok.ok) << ok.error;
  EXPECT_EQ(ok.scans, 22u);
  auto bad = good;
  bad[bad.size() / 2] ^= 1;
  const auto no = debug::check_recording(bad);
  EXPECT_FALSE(no.ok);
  EXPECT_TRUE(has(no.error, "recording damaged at scan")) << no.error;
  EXPECT_FALSE(debug::check_recording_file("/nonexistent.rec").ok);
}

// Writing to a full disk: the recording reports it and plcrun exits with 1
// (before: "recorded N scans", exit 0).
TEST(RecordingWrite, AFullDiskFailsTheRecordingAndPlcrunExitsNonZero) {
  struct stat st {};
  if (::stat("/dev/full", &st) != 0) GTEST_SKIP() << "no /dev/full here";
  auto r = plctest::run_command(plctest::plcrun_path() + " " + demo_path() +
                                " --cycles 2000 -q --record /dev/full");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "FAILED")) << r.output;
  EXPECT_TRUE(has(r.output, "No space left on device")) << r.output;
  EXPECT_FALSE(has(r.output, "recorded 2200 scans")) << r.output;
}

// The disk fills up in the middle of the run (a file size limit, as a
// nearly full disk): the same.
TEST(RecordingWrite, ADiskThatFillsUpDuringTheRunFailsTheRecording) {
  const std::string rec = plctest::temp_path("fsize.rec");
  auto r = plctest::run_command("trap '' XFSZ; ulimit -f 256; " + plctest::plcrun_path() + " " +
                                demo_path() + " --cycles 30000 -q --record " + rec);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "FAILED")) << r.output;
  const std::string err = debug::check_recording_file(rec).error;
  EXPECT_TRUE(has(err, "incomplete")) << err;
  std::remove(rec.c_str());
}

TEST(RecordingWrite, TheDebuggerReportsAFailedRecordingAtRecordStop) {
  struct stat st {};
  if (::stat("/dev/full", &st) != 0) GTEST_SKIP() << "no /dev/full here";
  const CellConfig cfg = load_cell_config(demo_path());
  debug::Debugger::Options o;
  o.span = std::chrono::minutes(1);
  debug::Debugger d([cfg] { return std::make_unique<Runtime>(cfg); }, o);
  d.execute("record /dev/full");
  d.execute("continue for 2s");
  const std::string out = d.execute("record stop");
  EXPECT_TRUE(has(out, "FAILED")) << out;
  EXPECT_TRUE(has(out, "No space left on device")) << out;
}

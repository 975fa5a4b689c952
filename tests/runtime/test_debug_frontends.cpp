// The debugger's front ends (issue 6): plcrun --commands, the console
// through a pseudo-terminal, --record/--replay on the command line, and
// pausing a real-time run next to a device with a communication watchdog.
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "plc/debug/debugger.hpp"
#include "plc/io/comm_watchdog_probe.hpp"
#include "plc/io/sim_plugin.hpp"
#include "test_helpers.hpp"
#include "test_programs.hpp"

using namespace plc;

namespace {

std::string demo() { return plctest::source_path("programs/demo/cell.yaml"); }

bool has(const std::string& out, const std::string& what) {
  return out.find(what) != std::string::npos;
}

// A debugger over a cell given as YAML text, running in real time.
std::unique_ptr<debug::Debugger> realtime_debugger(const std::string& yaml, const char* name) {
  const CellConfig cfg = parse_cell_config(yaml, name);
  debug::Debugger::Options o;
  o.mode = io::ClockMode::RealTime;
  o.span = std::chrono::seconds(60);
  return std::make_unique<debug::Debugger>([cfg] { return std::make_unique<Runtime>(cfg); }, o);
}

}  // namespace

namespace {

// Every debugger command with a piece of what it must print, in an order
// that makes a meaningful session on the demo cell. Both front ends run it.
struct Step {
  std::string command;
  std::string expect;
};

std::vector<Step> every_command(const std::string& vcd, const std::string& rec) {
  return {
      {"help", "goto SCAN"},
      {"step", "stepped 1 scan(s)"},
      {"step 9", "stepped 9 scan(s)"},
      {"step task slow", "of task 'slow'"},
      {"print Tank.hold_time %MX0.0", "Tank.hold_time = T#2s"},
      {"watch Tank.step", "  Tank.step = 1"},
      {"break Tank.step = 2", "breakpoint 1: Tank.step = 2"},
      {"breaks", "1: Tank.step = 2  hits 0"},
      {"continue", "breakpoint 1 (Tank.step = 2) hit"},
      {"delete all", "deleted 1 breakpoint(s)"},
      {"write Tank.low_level 3000", "will write Tank.low_level := 3000"},
      {"force Tank.high_level 9000", "force Tank.high_level := 9000"},
      {"forces", "Tank.high_level := 9000  (before: 22000)"},
      {"unforce Tank.high_level restore", "restoring 22000"},
      {"trace add Tank.level Tank.valve", "2 variable(s) Tank.level Tank.valve"},
      {"trace trigger Tank.step = 3", "trigger: Tank.step = 3"},
      {"trace pre 5", "pre-trigger rows: 5"},
      {"trace start " + vcd, "waiting for trigger"},
      {"record " + rec, "recording every scan's inputs"},
      {"run until Tank.step = 3", "condition 'Tank.step = 3' holds"},
      {"continue for 100ms", "ran for T#100ms"},
      {"trace", "triggered"},
      {"trace stop", "trace: stopped"},
      {"record stop", "recording stopped"},
      {"break before Tank if Tank.level < 19000",
       "breakpoint 2: before Tank if Tank.level < 19000"},
      {"continue", "frozen before program 'Tank'"},
      {"print Tank.step", "Tank.step = 3"},
      {"write Tank.step 1", "now, inside the scan"},
      {"step", "stepped from the freeze point to the end of the scan"},
      {"delete 2", "deleted 1 breakpoint(s)"},
      {"goto 10", "at scan 10; re-ran from the start"},
      {"unwatch Tank.step", ""},
      {"stats", "task fast: period T#1ms"},
      {"status", "at scan 10"},
      {"pause", "paused"},
      {"quit", ""},
  };
}

}  // namespace

TEST(DebugCommandsFile, EveryCommandRunsFromAFile) {
  const std::string vcd = plctest::temp_path("cmds.vcd");
  const std::string rec = plctest::temp_path("cmds.rec");
  std::string text;
  for (const Step& s : every_command(vcd, rec)) text += s.command + "\n";
  const std::string cmds = plctest::write_temp("cmds.txt", text);
  const auto r =
      plctest::run_command(plctest::plcrun_path() + " " + demo() + " --commands " + cmds);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::size_t at = 0;  // each answer after the previous one
  for (const Step& s : every_command(vcd, rec)) {
    const std::size_t p = r.output.find(s.expect, at);
    EXPECT_NE(p, std::string::npos) << "after '" << s.command << "' missing: " << s.expect << "\n"
                                    << r.output;
    if (p != std::string::npos) at = p;
  }
  EXPECT_TRUE(has(plctest::read_file(vcd), "$enddefinitions $end"));
  // The recording made in the session replays with identical outputs.
  const auto rp =
      plctest::run_command(plctest::plcrun_path() + " " + demo() + " --replay " + rec + " -q");
  EXPECT_EQ(rp.exit_code, 0) << rp.output;
  EXPECT_TRUE(has(rp.output, " 0 with different outputs")) << rp.output;
}

TEST(DebugCommandsFile, MissingFileIsAnError) {
  const auto r =
      plctest::run_command(plctest::plcrun_path() + " " + demo() + " --commands /nonexistent.txt");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(has(r.output, "cannot read command file")) << r.output;
}

TEST(RecordReplayCli, ABenchRunReplaysBitIdentically) {
  const std::string rec = plctest::temp_path("cli.rec");
  auto r = plctest::run_command(plctest::plcrun_path() + " " + demo() +
                                " --cycles 30000 -q --record " + rec);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "recorded 33000 scans")) << r.output;
  r = plctest::run_command(plctest::plcrun_path() + " " + demo() + " -q --replay " + rec);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "replay: 33000 scans, 0 with different outputs")) << r.output;
  r = plctest::run_command(plctest::plcrun_path() + " " + demo() + " -q --replay /nonexistent.rec");
  EXPECT_EQ(r.exit_code, 2);
}

// The console with line editing, through a pseudo-terminal.
TEST(DebugConsole, WorksThroughAPseudoTerminal) {
  int master = -1;
  const pid_t pid = forkpty(&master, nullptr, nullptr, nullptr);
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setenv("HOME", "/tmp", 1);
    setenv("TERM", "xterm", 1);
    const std::string bin = plctest::plcrun_path();
    const std::string cfg = demo();
    execl(bin.c_str(), bin.c_str(), cfg.c_str(), "--debug", static_cast<char*>(nullptr));
    _exit(127);
  }
  std::string screen;
  std::size_t mark = 0;  // where the output of the last command starts
  // Reads until `what` appears after `mark`; bounded by a generous deadline
  // so a broken console fails the test instead of hanging it.
  auto expect = [&](const std::string& what) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (screen.find(what, mark) == std::string::npos &&
           std::chrono::steady_clock::now() < deadline) {
      pollfd p{master, POLLIN, 0};
      if (poll(&p, 1, 100) > 0) {
        char buf[1024];
        const ssize_t n = read(master, buf, sizeof buf);
        if (n <= 0) break;
        screen.append(buf, std::size_t(n));
      }
    }
    return screen.find(what, mark) != std::string::npos;
  };
  // Keys typed before libedit has put the terminal in raw mode would be
  // handled by the kernel's cooked line discipline (a backspace would erase
  // there, Ctrl-P would be echoed as text): wait for raw mode, as a person
  // waits for the prompt. The master side reads the slave's termios.
  auto wait_raw = [&] {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    termios t{};
    while (tcgetattr(master, &t) == 0 && (t.c_lflag & ICANON) &&
           std::chrono::steady_clock::now() < deadline) {
      pollfd p{master, POLLIN, 0};
      if (poll(&p, 1, 1) > 0) {
        char buf[1024];
        const ssize_t n = read(master, buf, sizeof buf);
        if (n > 0) screen.append(buf, std::size_t(n));
      }
    }
  };
  auto send = [&](const std::string& keys) {
    wait_raw();
    mark = screen.size();
    ASSERT_EQ(write(master, keys.data(), keys.size()), ssize_t(keys.size()));
  };
  ASSERT_TRUE(expect("[scan 0 t=0.000000s] > ")) << screen;
  send("step 3\r");
  ASSERT_TRUE(expect("stepped 3 scan(s)")) << screen;
  ASSERT_TRUE(expect("[scan 3 t=0.001000s] > ")) << screen;
  send("print Tank.step\r");
  ASSERT_TRUE(expect("Tank.step = 1  (INT)")) << screen;
  ASSERT_TRUE(expect("[scan 3 t=0.001000s] > ")) << screen;
  // History and line editing: Ctrl-P recalls the previous line, Ctrl-A goes
  // to its start, '#' makes it a comment (runs nothing).
  send("\x10");
  ASSERT_TRUE(expect("print Tank.step")) << screen;
  send("\x01#\r");
  // "\n" + prompt: a fresh prompt after the line ran, not libedit redrawing
  // the line being edited (which repeats the prompt after a "\r").
  ASSERT_TRUE(expect("\n[scan 3 t=0.001000s] > ")) << screen;
  EXPECT_EQ(screen.find("Tank.step = 1", mark), std::string::npos) << "the comment ran nothing\n"
                                                                   << screen;
  // Two back is 'print Tank.step' again: Ctrl-E to its end, four
  // backspaces, and 'valve' make it 'print Tank.valve'.
  send("\x10\x10\x05\x7f\x7f\x7f\x7fvalve\r");
  ASSERT_TRUE(expect("Tank.valve = 0  (INT %QW0)")) << screen;
  EXPECT_EQ(screen.find("unknown command", mark), std::string::npos) << screen;
  ASSERT_TRUE(expect("\n[scan 3 ")) << screen;
  // Then every command, typed at the console.
  for (const Step& st :
       every_command(plctest::temp_path("pty.vcd"), plctest::temp_path("pty.rec"))) {
    send(st.command + "\r");
    if (st.command == "quit") break;
    EXPECT_TRUE(expect(st.expect)) << "after '" << st.command << "' missing: " << st.expect << "\n"
                                   << screen.substr(mark);
    EXPECT_TRUE(expect("] > ")) << screen.substr(mark);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  close(master);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << screen;
}

// Pausing a real-time run for 2 s next to a simulated device with a 500 ms
// communication watchdog does not trip it: the logic stops, the bus goes on.
// (500 ms, not less: the sim plugin's thread may be stalled for 100 ms on a
// loaded machine, and the pause still lasts four watchdog times.)
TEST(DebugRealTime, PausingForTwoSecondsKeepsTheBusAliveAndTheDeviceHappy) {
  auto dbg = realtime_debugger(R"(
tasks: [{name: main, period: 1ms, programs: [Loop]}]
programs: [{name: Loop, type: LoopCounter, bind: {to_dev: "%QD8", from_dev: "%ID8"}}]
plugins: [{name: sim, params: {step: 1ms}}]
devices:
  - {name: probe, plugin: sim, model: comm_watchdog, input: "%IB0", output: "%QB0", params: {timeout: 500ms}}
)",
                               "rt_pause.yaml");
  debug::Debugger& d = *dbg;
  EXPECT_TRUE(has(d.execute("pause"), "paused"));
  EXPECT_TRUE(has(d.execute("step 5"), "stepped 5 scan(s) of each task"));
  auto* loop = static_cast<plctest::LoopCounter*>(d.runtime().program("Loop"));
  auto* sim = static_cast<io::SimPlugin*>(d.runtime().plugin("sim"));
  auto& probe = static_cast<io::CommWatchdogProbe&>(sim->device("probe")->model());
  const auto count_before = loop->count;
  const auto exchanges_before = probe.exchanges();
  std::this_thread::sleep_for(std::chrono::seconds(2));  // the pause under test
  EXPECT_EQ(loop->count, count_before) << "the logic did not scan while paused";
  EXPECT_GT(probe.exchanges() - exchanges_before, 1000u)
      << "the bus kept exchanging (1 ms steps for 2 s)";
  EXPECT_FALSE(probe.tripped()) << "longest gap " << probe.longest_gap().count() << " ns";
  EXPECT_TRUE(has(d.execute("step 3"), "stepped 3 scan(s)"));
  EXPECT_EQ(loop->count, count_before + 3);
  EXPECT_TRUE(
      has(d.execute("print Loop.count"), "Loop.count = " + std::to_string(count_before + 3)));
  EXPECT_TRUE(has(d.execute("continue"), "running"));
  EXPECT_TRUE(has(d.execute("stats"), "releases paused"));
  d.execute("quit");
}

// A breakpoint in real time pauses the logic at the end of the very scan
// that hit it (the task thread sets the pause before its next release).
TEST(DebugRealTime, BreakpointPausesAtTheScanThatHitIt) {
  auto dbg = realtime_debugger(R"(
tasks: [{name: main, period: 1ms, programs: [Loop]}]
programs: [{name: Loop, type: LoopCounter}]
)",
                               "rt_break.yaml");
  debug::Debugger& d = *dbg;
  std::string out = d.execute("run until Loop.count = 150");
  EXPECT_TRUE(has(out, "condition 'Loop.count = 150' holds")) << out;
  auto* loop = static_cast<plctest::LoopCounter*>(d.runtime().program("Loop"));
  EXPECT_EQ(loop->count, 150);
  EXPECT_TRUE(has(d.prompt(), "paused"));
  EXPECT_TRUE(has(d.execute("break Loop.count = 400"), "breakpoint 1"));
  out = d.execute("run until Loop.count > 10000");  // the breakpoint comes first
  EXPECT_TRUE(has(out, "breakpoint 1 (Loop.count = 400) hit")) << out;
  EXPECT_EQ(loop->count, 400);
  d.execute("quit");
}

// Printing while a real-time task runs reads the task's variables at the end
// of one of its scans: two variables the scan sets at its start and its end
// are always printed equal, never a half-done scan. (No watchdog: the scan
// takes 300 us of each 1 ms, so a 100 ms stall of a loaded machine would
// often land in one and trip it.)
TEST(DebugRealTime, PrintWhileRunningShowsOneWholeScan) {
  auto dbg = realtime_debugger(R"(
tasks: [{name: main, period: 1ms, watchdog: 0, programs: [Pair]}]
programs: [{name: Pair, type: PairWriter}]
)",
                               "rt_print.yaml");
  debug::Debugger& d = *dbg;
  EXPECT_TRUE(has(d.execute("continue"), "running"));
  long last = -1;
  int increasing = 0;
  for (int i = 0; i < 200; ++i) {
    const std::string out = d.execute("print Pair.first Pair.second");
    long first = -1, second = -2;
    ASSERT_EQ(
        std::sscanf(out.c_str(), "Pair.first = %ld  (DINT)\nPair.second = %ld", &first, &second), 2)
        << out;
    ASSERT_EQ(first, second) << "read in the middle of a scan:\n" << out;
    increasing += first > last;
    last = first;
  }
  EXPECT_GT(increasing, 100) << "the task kept running while we printed";
  d.execute("quit");
}

// plcrun's command line: --list-vars, --stats-json, --trace errors, usage
// errors, and a clean stop on SIGINT in real time.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "test_helpers.hpp"

namespace {

std::string demo() { return plctest::source_path("programs/demo/cell.yaml"); }

// The demo cell without watchdogs: the real-time tests here are about the
// command line, and a loaded machine that stalls a scan for more than 10
// periods must not stop them (exit 1).
std::string realtime_demo() {
  const std::string cell = plctest::demo_without_watchdogs("cli_realtime_demo.yaml");
  EXPECT_FALSE(cell.empty()) << "programs/demo/cell.yaml changed: see demo_without_watchdogs()";
  return cell;
}

}  // namespace

TEST(PlcrunCli, ListVarsPrintsPathTypeAndAddress) {
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + demo() + " --list-vars");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("Tank.hold.ET TIME\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Tank.level INT %IW0\n"), std::string::npos);
  EXPECT_NE(r.output.find("Supervisor.lamp_running BOOL %QX2.0\n"), std::string::npos);
}

TEST(PlcrunCli, SummaryGivesEachDevicesPluginDiagnostics) {
  // The plugin's own account of each device (state, counters) ends the
  // summary: for the sim plugin its state.
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + demo() + " --cycles 10");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("device tank1      (sim): online\n"), std::string::npos) << r.output;
}

TEST(PlcrunCli, TraceInADebuggerSessionIsRefusedNotLeftOut) {
  // A --commands or --debug session takes its trace from the debugger's
  // commands; --trace there used to be ignored without a word.
  const std::string cmds = plctest::write_temp("cli_trace_cmds.txt", "continue for T#10ms\n");
  const std::string csv = plctest::temp_path("cli_trace.csv");
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + demo() + " --commands " +
                                      cmds + " --trace " + csv + " --trace-vars Tank.level");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--trace applies to a plain run"), std::string::npos) << r.output;
}

TEST(PlcrunCli, StatsJsonHasEveryTask) {
  const std::string file = plctest::temp_path("stats.json");
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + demo() +
                                      " --cycles 1000 -q --stats-json " + file);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string j = plctest::read_file(file);
  EXPECT_NE(j.find("\"name\": \"fast\", \"period_ns\": 1000000"), std::string::npos) << j;
  EXPECT_NE(j.find("\"scans\": 1000,"), std::string::npos) << j;
  EXPECT_NE(j.find("\"scans\": 100,"), std::string::npos) << "slow task: 10 ms" << j;
  EXPECT_NE(j.find("\"p999\""), std::string::npos);
}

// Issue 21 follow-up, point 6: where the run's results go (--stats-json,
// --trace, --record) is checked before the cell starts, like the retain
// file: a folder that does not exist, a "folder" that is a file, a path
// that is a folder. Before, --stats-json was found unwritable after the run.
TEST(PlcrunCli, OutputFilesThatCannotBeWrittenAreRefusedBeforeTheRun) {
  const std::string file = plctest::write_temp("cli_not_a_folder", "x");
  const std::string dir = plctest::temp_path("cli_a_folder");
  std::filesystem::create_directories(dir);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--stats-json /nonexistent-softplc/stats.json",
       "the folder '/nonexistent-softplc' does not exist"},
      {"--stats-json " + file + "/stats.json", "'" + file + "' is not a folder"},
      {"--stats-json " + dir, "is a folder, not a file"},
      {"--trace /nonexistent-softplc/t.csv --trace-vars Tank.level",
       "the folder '/nonexistent-softplc' does not exist"},
      {"--record /nonexistent-softplc/r.plcrec",
       "the folder '/nonexistent-softplc' does not exist"},
      // --checks' verdict (scenario campaigns): refused before the checks are
      // even read, so any campaign file does here.
      {"--checks " + plctest::source_path("programs/filling_cell/campaign/filling_campaign.yaml") +
           " --results-json /nonexistent-softplc/r.json",
       "the folder '/nonexistent-softplc' does not exist"},
  };
  for (const auto& [args, why] : cases) {
    const std::string cmd = plctest::plcrun_path() + " " + demo() + " --cycles 10 -q " + args;
    const auto r = plctest::run_command(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.output;
    EXPECT_NE(r.output.find("cannot write"), std::string::npos) << cmd << "\n" << r.output;
    EXPECT_NE(r.output.find(why), std::string::npos) << cmd << "\n" << r.output;
    EXPECT_EQ(r.output.find("running cell"), std::string::npos)
        << "the cell ran first: " << cmd << "\n"
        << r.output;
    EXPECT_EQ(r.output.find("== summary"), std::string::npos) << cmd << "\n" << r.output;
  }
}

TEST(PlcrunCli, UsageErrorsExitWithTwo) {
  for (const char* args : {"", " --cycles 5 --for 1s", " --trace x.csv", " --virtual --realtime",
                           " --for soon", " --bogus"}) {
    const std::string cmd =
        plctest::plcrun_path() + (std::string(args).empty() ? "" : " " + demo()) + args;
    const auto r = plctest::run_command(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.output;
  }
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + demo() +
                                      " --cycles 5 --trace /tmp/x.csv --trace-vars Tank.nope");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown variable 'Tank.nope'"), std::string::npos) << r.output;
  const auto r2 = plctest::run_command(
      plctest::plcrun_path() + " " + demo() +
      " --cycles 5 --trace /tmp/x.csv --trace-vars Tank.level --trace-trigger 'Tank.level >'");
  EXPECT_EQ(r2.exit_code, 2);
  EXPECT_NE(r2.output.find("incomplete condition"), std::string::npos) << r2.output;
}

TEST(PlcrunCli, SigintStopsARealTimeRunCleanly) {
  const std::string cfg = realtime_demo();
  int out_pipe[2];
  ASSERT_EQ(pipe(out_pipe), 0);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    dup2(out_pipe[1], STDOUT_FILENO);
    dup2(out_pipe[1], STDERR_FILENO);
    close(out_pipe[0]);
    const std::string bin = plctest::plcrun_path();
    execl(bin.c_str(), bin.c_str(), cfg.c_str(), "--realtime", "--for", "60s",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  close(out_pipe[1]);
  // Wait (blocking read, no sleep) until plcrun says it is running.
  std::string out;
  char buf[512];
  while (out.find("running") == std::string::npos) {
    const ssize_t n = read(out_pipe[0], buf, sizeof buf);
    if (n <= 0) break;
    out.append(buf, std::size_t(n));
  }
  ASSERT_NE(out.find("running"), std::string::npos) << out;
  kill(pid, SIGINT);
  ssize_t n;
  while ((n = read(out_pipe[0], buf, sizeof buf)) > 0) out.append(buf, std::size_t(n));
  close(out_pipe[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << out;
  EXPECT_EQ(WEXITSTATUS(status), 0) << out;
  EXPECT_NE(out.find("stopped by signal; outputs at their safe values"), std::string::npos) << out;
  EXPECT_NE(out.find("== summary"), std::string::npos) << out;
}

// Issue 10 point 9: the tests run the plcrun of their own build, whatever the
// build folder is called (they used to fall back to build/bin when ctest lost
// PLC_BIN_DIR, and so ran a stale plcrun, or none, from another build).
TEST(PlcrunCli, TestsRunThePlcrunBuiltNextToThem) {
  namespace fs = std::filesystem;
  const fs::path self = fs::read_symlink("/proc/self/exe").parent_path();
  const fs::path plcrun = plctest::plcrun_path();
  ASSERT_TRUE(fs::exists(plcrun)) << plcrun;
  EXPECT_TRUE(fs::equivalent(plcrun.parent_path(), self))
      << plcrun << " is not in this test's build folder " << self;
}

// Issue 10 point 8: the command line's numbers have ranges. --cycles times
// the fastest period overflowed TIME, --trace-pre 2^64-1 made a ring of 0
// slots (a division by zero at the first sample), --for had no upper end.
// (`timeout` bounds the old behaviour.)
TEST(PlcrunCli, RunLengthAndPretriggerOutsideTheirRangesAreUsageErrors) {
  const std::string trace = plctest::temp_path("pre.csv");
  struct Row {
    std::string args;
    const char* message;
  };
  const Row rows[] = {
      {" --cycles 18446744073709551615", "--cycles: 18446744073709551615 out of range [1, "},
      {" --cycles=-1", "--cycles: 18446744073709551615 out of range [1, "},
      {" --cycles 0", "--cycles: 0 out of range [1, 3153600000000]"},
      {" --for 36501d", "--for: '36501d' is not a duration from 1ns to T#36500d"},
      {" --cycles 5 --trace " + trace +
           " --trace-vars Tank.level --trace-trigger 'Tank.level > 30000'"
           " --trace-pre 18446744073709551615",
       "--trace-pre: 18446744073709551615 out of range [0, 1000000]"},
  };
  for (const Row& r : rows) {
    const auto out =
        plctest::run_command("timeout 60 " + plctest::plcrun_path() + " " + demo() + r.args);
    EXPECT_EQ(out.exit_code, 2) << r.args << ": " << out.output;
    EXPECT_NE(out.output.find(r.message), std::string::npos) << r.args << ": " << out.output;
    EXPECT_EQ(out.output.find("summary"), std::string::npos) << r.args << ": " << out.output;
  }
  std::remove(trace.c_str());
}

// Issue 10 point 5: --list-vars marks a block's internal state read-only.
TEST(PlcrunCli, ListVarsMarksInternalStateReadOnly) {
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + demo() + " --list-vars");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("Tank.hold.start_ TIME read-only\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Tank.drained.M BOOL read-only\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Tank.hold.PT TIME\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Tank.step INT\n"), std::string::npos) << "program variables: writable";
}

namespace {

// plcrun as a child with its stdout+stderr (and optionally its stdin) on
// pipes; every wait is bounded by a deadline so a hang fails the test.
struct Child {
  pid_t pid = -1;
  int out = -1;
  int in = -1;
  bool eof = false;
  std::string output;

  Child(const std::vector<std::string>& args, bool with_stdin) {
    int o[2], i[2] = {-1, -1};
    if (pipe(o) != 0 || (with_stdin && pipe(i) != 0)) return;
    pid = fork();
    if (pid == 0) {
      dup2(o[1], STDOUT_FILENO);
      dup2(o[1], STDERR_FILENO);
      close(o[0]);
      if (with_stdin) {
        dup2(i[0], STDIN_FILENO);
        close(i[1]);
      }
      std::vector<char*> argv;
      const std::string bin = plctest::plcrun_path();
      argv.push_back(const_cast<char*>(bin.c_str()));
      for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(bin.c_str(), argv.data());
      _exit(127);
    }
    close(o[1]);
    out = o[0];
    if (with_stdin) {
      close(i[0]);
      in = i[1];
    }
  }
  // Reads until `what` appears after `from` (or EOF, or `limit`).
  bool read_until(const std::string& what, std::size_t from = 0,
                  std::chrono::milliseconds limit = std::chrono::seconds(30)) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (output.find(what, from) == std::string::npos &&
           std::chrono::steady_clock::now() < deadline) {
      pollfd p{out, POLLIN, 0};
      if (poll(&p, 1, 100) <= 0) continue;
      char buf[4096];
      const ssize_t n = read(out, buf, sizeof buf);
      if (n <= 0) {
        eof = true;
        break;
      }
      output.append(buf, std::size_t(n));
    }
    return output.find(what, from) != std::string::npos;
  }
  void type(const std::string& text) const {
    ASSERT_EQ(write(in, text.data(), text.size()), ssize_t(text.size()));
  }
  // Reads to EOF and reaps the child; its exit code (-1: no normal exit).
  int finish() {
    read_until(std::string(1, '\0'));  // to EOF (a NUL never comes)
    if (in >= 0) close(in);
    close(out);
    if (!eof) kill(pid, SIGKILL);  // no EOF within the deadline: it hangs
    int status = 0;
    waitpid(pid, &status, 0);
    if (!eof) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
};

}  // namespace

// Issue 10 point 7: SIGTERM ends a --commands session (before: it only
// interrupted the running command and the script went on, exit 0). The
// session stops at the next scan boundary, the outputs go to their safe
// values, the summary is printed, and plcrun exits with 128 + 15.
TEST(PlcrunCli, SigtermEndsACommandsSessionWithTheSummaryAndExit143) {
  const std::string cmds = plctest::write_temp("term_cmds.txt",
                                               "continue\n"
                                               "print Tank.step\n"
                                               "quit\n");
  Child c({demo(), "--for", "3650d", "--commands", cmds}, false);
  ASSERT_GT(c.pid, 0);
  // A ten-year continue in virtual time: still running when the signal comes.
  ASSERT_TRUE(c.read_until("] > continue\n")) << c.output;
  kill(c.pid, SIGTERM);
  EXPECT_EQ(c.finish(), 143) << c.output;
  EXPECT_NE(c.output.find("stopped: the session is ending (signal)"), std::string::npos)
      << c.output;
  EXPECT_EQ(c.output.find("> print Tank.step"), std::string::npos)
      << "no command runs after SIGTERM\n"
      << c.output;
  EXPECT_NE(c.output.find("== summary"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("stopped by SIGTERM; outputs at their safe values"), std::string::npos)
      << c.output;
}

// Without a console, Ctrl-C ends the session the same way (128 + 2).
TEST(PlcrunCli, SigintEndsACommandsSessionWithoutAConsole) {
  const std::string cmds = plctest::write_temp("int_cmds.txt", "continue\nprint Tank.step\n");
  Child c({demo(), "--for", "3650d", "--commands", cmds}, false);
  ASSERT_GT(c.pid, 0);
  ASSERT_TRUE(c.read_until("] > continue\n")) << c.output;
  kill(c.pid, SIGINT);
  EXPECT_EQ(c.finish(), 130) << c.output;
  EXPECT_EQ(c.output.find("> print Tank.step"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("stopped by SIGINT; outputs at their safe values"), std::string::npos)
      << c.output;
}

// At the console (--debug) Ctrl-C still only interrupts the running command;
// SIGTERM ends the session there too.
TEST(PlcrunCli, SigintAtTheConsoleOnlyInterruptsSigtermEndsTheSession) {
  const std::string cmds = plctest::write_temp("con_cmds.txt", "continue\n");
  Child c({demo(), "--for", "3650d", "--commands", cmds, "--debug"}, true);
  ASSERT_GT(c.pid, 0);
  ASSERT_TRUE(c.read_until("] > continue\n")) << c.output;
  // The signal may come before the command has begun (then it is lost, as
  // a Ctrl-C typed just before Enter): repeat it until the run stops.
  for (int i = 0; i < 300 && c.output.find("stopped: interrupted") == std::string::npos; ++i) {
    kill(c.pid, SIGINT);
    c.read_until("stopped: interrupted", 0, std::chrono::milliseconds(100));
  }
  ASSERT_NE(c.output.find("stopped: interrupted"), std::string::npos) << c.output;
  const std::size_t mark = c.output.size();
  c.type("print Tank.hold_time\n");
  ASSERT_TRUE(c.read_until("Tank.hold_time = T#2s", mark)) << "the console went on\n" << c.output;
  ASSERT_TRUE(c.read_until("] > ", c.output.find("Tank.hold_time = T#2s", mark)));
  kill(c.pid, SIGTERM);  // the console is waiting for a line: it ends too
  EXPECT_EQ(c.finish(), 143) << c.output;
  EXPECT_NE(c.output.find("stopped by SIGTERM; outputs at their safe values"), std::string::npos)
      << c.output;
}

// The same in real time: the tasks are stopped (outputs safe) before the
// summary reads their statistics.
TEST(PlcrunCli, SigtermEndsARealTimeDebugSession) {
  const std::string cmds = plctest::write_temp("rt_term_cmds.txt", "continue\n");
  Child c({demo(), "--realtime", "--commands", cmds, "--debug"}, true);
  ASSERT_GT(c.pid, 0);
  ASSERT_TRUE(c.read_until("running (pause, or a breakpoint, stops it)")) << c.output;
  kill(c.pid, SIGTERM);
  EXPECT_EQ(c.finish(), 143) << c.output;
  EXPECT_NE(c.output.find("== summary: cell 'demo', real time"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("stopped by SIGTERM; outputs at their safe values"), std::string::npos)
      << c.output;
}

// Issue 21 point 6: --print-vars in a cell with an hmi: section (a debugger
// session without a console) was ignored without a word; it prints after
// the summary, as in a plain run.
TEST(PlcrunCli, PrintVarsInACellWithAnHmiSectionArePrinted) {
  const std::string cfg = plctest::write_temp(
      "cli_hmi_print.yaml",
      plctest::read_file(demo()) + "\nhmi:\n  url: memq://\n  publish: [\"Tank.*\"]\n");
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + cfg +
                                      " --for 1s -q --print-vars Tank.hold_time,Tank.nope");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = r.output.find("== summary");
  const auto values = r.output.find("final values:\n  Tank.hold_time = T#2s\n");
  ASSERT_NE(summary, std::string::npos) << r.output;
  ASSERT_NE(values, std::string::npos) << r.output;
  EXPECT_GT(values, summary) << r.output;
  EXPECT_NE(r.output.find("  Tank.nope = <unknown variable>\n"), std::string::npos) << r.output;
}

// ... and in a --commands or --debug session, which may goto, restart and
// run on after its last command, it is refused with the way to print there.
TEST(PlcrunCli, PrintVarsInADebuggerSessionIsRefusedNotLeftOut) {
  const std::string cmds = plctest::write_temp("cli_print_cmds.txt", "continue for T#10ms\n");
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + demo() + " --commands " +
                                      cmds + " --print-vars Tank.level");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--print-vars applies to a plain run or a cell with an hmi: section"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("continue for"), std::string::npos) << "nothing ran\n" << r.output;
}

// Issue 21 point 6: the live status line of a real-time run showed t=0.00 s
// all along (it read the virtual clock). Piped, plcrun prints it as lines;
// the first comes after 256 scans, so its time is past 0. No other figure
// is checked: it depends on the machine.
TEST(PlcrunCli, StatusLineInRealTimeShowsTheTimeOfTheScans) {
  Child c({realtime_demo(), "--realtime", "--for", "60s"}, false);
  ASSERT_GT(c.pid, 0);
  ASSERT_TRUE(c.read_until("[realtime] t=")) << c.output;
  const std::size_t at = c.output.find("[realtime] t=");
  ASSERT_TRUE(c.read_until("\n", at)) << c.output;
  double t = -1;
  ASSERT_EQ(std::sscanf(c.output.c_str() + at, "[realtime] t=%lf s", &t), 1) << c.output;
  EXPECT_GT(t, 0.0) << c.output.substr(at, c.output.find('\n', at) - at);
  kill(c.pid, SIGINT);
  EXPECT_EQ(c.finish(), 0) << c.output;
  EXPECT_NE(c.output.find("stopped by signal; outputs at their safe values"), std::string::npos)
      << c.output;
}

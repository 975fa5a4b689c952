// plcrun's command line: --list-vars, --stats-json, --trace errors, usage
// errors, and a clean stop on SIGINT in real time.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

#include "test_helpers.hpp"

namespace {

std::string demo() { return plctest::source_path("programs/demo/cell.yaml"); }

}  // namespace

TEST(PlcrunCli, ListVarsPrintsPathTypeAndAddress) {
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + demo() + " --list-vars");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("Tank.hold.ET TIME\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Tank.level INT %IW0\n"), std::string::npos);
  EXPECT_NE(r.output.find("Supervisor.lamp_running BOOL %QX2.0\n"), std::string::npos);
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
  int out_pipe[2];
  ASSERT_EQ(pipe(out_pipe), 0);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    dup2(out_pipe[1], STDOUT_FILENO);
    dup2(out_pipe[1], STDERR_FILENO);
    close(out_pipe[0]);
    const std::string bin = plctest::plcrun_path();
    const std::string cfg = demo();
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

// plcrun's HMI host starting and watching plchmi, the bridge's own process
// (issue 22, "Process isolation"): killed with SIGKILL or SIGSEGV it is
// started again with backoff, each outage noted (the bridge's hmi_lost
// alarm once it is back); it runs as an unprivileged user without any
// capability, holding only the shared memory and the doorbell; it joins the
// configured network namespace; it is reaped when the host stops. The host
// runs in this process with a real-time cell, plchmi as the real process
// (memq://: it talks to nobody, which is all these tests need).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "hmi_test_cell.hpp"
#include "plc/hmi/host.hpp"
#include "runtime/test_helpers.hpp"

using namespace plc;

namespace {

using Clock = std::chrono::steady_clock;

std::string status_field(int pid, const std::string& key) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind(key + ":", 0) == 0) {
      std::string v = line.substr(key.size() + 1);
      v.erase(0, v.find_first_not_of(" \t"));
      v.erase(v.find_last_not_of(" \t") + 1);
      return v;
    }
  return "";
}

// The demo cell (real time, no watchdog) with `hmi` on memq://, its host
// supervising plchmi from build/bin.
struct Supervised {
  CellConfig cfg;
  std::unique_ptr<Runtime> rt;
  std::unique_ptr<hmi::Host> host;
  std::thread scans;
  mutable std::mutex mu;
  std::vector<std::string> log;

  explicit Supervised(const std::string& extra = "", hmi::Supervisor::Backoff backoff = fast()) {
    std::string cell = plctest::demo_yaml();
    const auto wd = cell.find("watchdog: 10");
    if (wd != std::string::npos) cell.replace(wd, 12, "watchdog: 0 ");
    cfg = parse_cell_config(cell + "\nhmi:\n  url: memq://\n  publish: [\"Tank.*\"]\n" + extra,
                            "supervised.yaml");
    rt = std::make_unique<Runtime>(cfg);
    hmi::Host::Options o;
    o.plchmi = plctest::bin_dir() + "/plchmi";
    o.backoff = backoff;
    o.log = [this](const std::string& l) {
      std::lock_guard<std::mutex> lock(mu);
      log.push_back(l);
    };
    host = std::make_unique<hmi::Host>(cfg.hmi, cfg.file, std::move(o));
    host->attach(*rt);
  }
  ~Supervised() {
    host->stop();
    if (scans.joinable()) {
      rt->request_stop();
      scans.join();
    }
  }
  static hmi::Supervisor::Backoff fast() {
    hmi::Supervisor::Backoff b;
    b.first = std::chrono::milliseconds(100);
    b.max = std::chrono::milliseconds(400);
    b.reset_after = std::chrono::seconds(60);
    return b;
  }
  void run_cell(std::chrono::seconds span) {
    rt->start(io::ClockMode::RealTime);
    scans = std::thread([this, span] { rt->run(io::ClockMode::RealTime, span); });
  }
  // plchmi's pid once it is one other than `not_this` (bounded: 10 s).
  int wait_pid(int not_this = 0) const {
    for (int i = 0; i < 1000; ++i) {
      const int pid = host->bridge_pid();
      if (pid > 0 && pid != not_this) return pid;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return 0;
  }
  // ... and set up: past the dynamic loader, its bridge made (bounded: 10 s).
  int wait_up() const {
    const int pid = wait_pid();
    for (int i = 0; pid > 0 && i < 1000; ++i) {
      if (host->regions().control().bridge_pid.load() == std::uint64_t(pid)) return pid;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return 0;
  }
  std::string lines() const {
    std::lock_guard<std::mutex> lock(mu);
    std::string s;
    for (const auto& l : log) s += l + "\n";
    return s;
  }
};

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

}  // namespace

// Killed again and again, plchmi comes back each time after a delay that
// doubles up to the maximum; each exit is logged with its signal and noted
// as an outage.
TEST(HmiSupervisedRealTime, KilledBridgeIsRestartedWithBackoff) {
  Supervised s;
  s.host->start();
  int pid = s.wait_pid();
  ASSERT_GT(pid, 0) << s.lines();
  for (int sig : {SIGKILL, SIGSEGV, SIGKILL, SIGSEGV}) {
    ASSERT_EQ(kill(pid, sig), 0);
    const int next = s.wait_pid(pid);
    ASSERT_GT(next, 0) << s.lines();
    pid = next;
  }
  const std::string log = s.lines();
  EXPECT_EQ(count(log, "plchmi exited (signal 9, KILL)"), 2U) << log;
  EXPECT_EQ(count(log, "plchmi exited (signal 11, SEGV)"), 2U) << log;
  // 0.1, 0.2, 0.4, then held at the maximum.
  EXPECT_NE(log.find("SEGV); restart in 0.2 s"), std::string::npos) << log;
  EXPECT_NE(log.find("KILL); restart in 0.4 s"), std::string::npos) << log;
  EXPECT_NE(log.find("SEGV); restart in 0.4 s"), std::string::npos) << log;
  EXPECT_EQ(count(log, "plchmi back"), 4U) << log;
  const auto summary = s.host->summary();
  ASSERT_FALSE(summary.empty());
  EXPECT_NE(summary[0].find("started 5 time(s), 4 outage(s)"), std::string::npos) << summary[0];
}

// Up longer than reset_after, a crash is a new trouble: the delay starts
// again from the first.
TEST(HmiSupervisedRealTime, BackoffStartsAgainAfterALongRun) {
  hmi::Supervisor::Backoff b = Supervised::fast();
  b.reset_after = std::chrono::milliseconds(300);
  Supervised s("", b);
  s.host->start();
  int pid = s.wait_pid();
  ASSERT_GT(pid, 0);
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  pid = s.wait_pid(pid);
  ASSERT_GT(pid, 0);
  ASSERT_EQ(kill(pid, SIGKILL), 0);  // at once: doubled
  pid = s.wait_pid(pid);
  ASSERT_GT(pid, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(400));  // up past reset_after
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  ASSERT_GT(s.wait_pid(pid), 0);
  const std::string log = s.lines();
  EXPECT_EQ(count(log, "restart in 0.1 s"), 2U) << log;
  EXPECT_EQ(count(log, "restart in 0.2 s"), 1U) << log;
}

// The cell scans on while its bridge crashes and restarts three times: in
// real time, the second with the crashes has no more overruns than the
// steady seconds before and after it (generous: plus a few, for a loaded
// machine), and the scans go on at their rate.
TEST(HmiSupervisedRealTime, CellKeepsScanningWhileTheBridgeCrashes) {
  Supervised s;
  s.run_cell(std::chrono::seconds(60));
  s.host->start();
  int pid = s.wait_pid();
  ASSERT_GT(pid, 0);
  const TaskRuntime& fast = *s.rt->tasks()[0];
  auto window = [&](bool crash) {
    const TaskStats a = fast.stats.snapshot();
    const auto end = Clock::now() + std::chrono::seconds(1);
    int kills = 0;
    while (Clock::now() < end) {
      if (crash && kills < 3 && s.host->bridge_pid() > 0) {
        kill(s.host->bridge_pid(), SIGSEGV);
        ++kills;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    const TaskStats b = fast.stats.snapshot();
    return std::pair{b.overruns - a.overruns, b.scans - a.scans};
  };
  const auto before = window(false);
  const auto during = window(true);
  const auto after = window(false);
  ::testing::Test::RecordProperty("overruns_before", int(before.first));
  ::testing::Test::RecordProperty("overruns_during", int(during.first));
  ::testing::Test::RecordProperty("overruns_after", int(after.first));
  EXPECT_LE(during.first, std::max(before.first, after.first) + 5)
      << "before " << before.first << ", during " << during.first << ", after " << after.first;
  EXPECT_GT(during.second, 500U) << "the 1 ms task ran " << during.second << " scans";
  EXPECT_GE(count(s.lines(), "SEGV"), 1U) << s.lines();
}

// plcrun as root: plchmi runs as nobody, with no capability in any set,
// no new privileges, and no descriptor but stdio, the two shared-memory
// regions (the state one mapped read-only) and the doorbell.
TEST(HmiSupervisedRealTime, BridgeRunsUnprivileged) {
  if (geteuid() != 0) GTEST_SKIP() << "plcrun drops plchmi's privileges only when it is root";
  Supervised s;
  s.host->start();
  const int pid = s.wait_up();
  ASSERT_GT(pid, 0) << s.lines();
  EXPECT_EQ(status_field(pid, "Uid"), "65534\t65534\t65534\t65534");
  EXPECT_EQ(status_field(pid, "Gid"), "65534\t65534\t65534\t65534");
  EXPECT_EQ(status_field(pid, "Groups"), "65534");
  for (const char* caps : {"CapInh", "CapPrm", "CapEff", "CapBnd", "CapAmb"})
    EXPECT_EQ(status_field(pid, caps), "0000000000000000") << caps;
  EXPECT_EQ(status_field(pid, "NoNewPrivs"), "1");
  // Its descriptors: 0-2, then state, control, doorbell; memq:// opens
  // nothing of its own but pipes.
  const std::string fds = plctest::run_command("ls -l /proc/" + std::to_string(pid) + "/fd").output;
  EXPECT_NE(fds.find("3 -> /memfd:plc-hmi-state"), std::string::npos) << fds;
  EXPECT_NE(fds.find("4 -> /memfd:plc-hmi-control"), std::string::npos) << fds;
  EXPECT_NE(fds.find("5 -> anon_inode:[eventfd]"), std::string::npos) << fds;
  std::istringstream in(fds);
  std::string line;
  for (int i = 0; i < 100 && std::getline(in, line); ++i) {
    const auto arrow = line.find(" -> ");
    if (arrow == std::string::npos) continue;
    const std::string target = line.substr(arrow + 4);
    const bool known = target.rfind("/memfd:plc-hmi-", 0) == 0 ||
                       target.rfind("anon_inode:", 0) == 0 || target.rfind("pipe:", 0) == 0 ||
                       target.rfind("socket:", 0) == 0 || target.rfind("/dev/", 0) == 0;
    const bool stdio = line.find(" 1 -> ") != std::string::npos ||
                       line.find(" 2 -> ") != std::string::npos;
    EXPECT_TRUE(known || stdio) << "plchmi holds " << line;
  }
  const std::string maps = plctest::read_file("/proc/" + std::to_string(pid) + "/maps");
  const auto at = maps.find("/memfd:plc-hmi-state");
  ASSERT_NE(at, std::string::npos) << maps;
  const auto bol = maps.rfind('\n', at) + 1;
  EXPECT_EQ(maps.substr(maps.find(' ', bol) + 1, 4), "r--s") << maps.substr(bol, at - bol);
}

// `netns:` puts plchmi into that network namespace (here one that a
// sleeping child of this test holds: /proc/PID/ns/net).
TEST(HmiSupervisedRealTime, BridgeJoinsTheConfiguredNetworkNamespace) {
  if (geteuid() != 0) GTEST_SKIP() << "joining a network namespace needs root";
  if (plctest::run_command("unshare --net true").exit_code != 0)
    GTEST_SKIP() << "network namespaces are not available here";
  const pid_t holder = fork();
  ASSERT_GE(holder, 0);
  if (holder == 0) {
    execlp("unshare", "unshare", "--net", "sleep", "30", static_cast<char*>(nullptr));
    _exit(127);
  }
  struct Reap {
    pid_t p;
    ~Reap() {
      kill(p, SIGKILL);
      waitpid(p, nullptr, 0);
    }
  } reap{holder};
  // unshare execs sleep in the new namespace: wait until it has (bounded).
  auto ns_of = [](int pid) {
    struct stat st {};
    return stat(("/proc/" + std::to_string(pid) + "/ns/net").c_str(), &st) == 0 ? st.st_ino
                                                                                : ino_t(0);
  };
  for (int i = 0; i < 500 && ns_of(holder) == ns_of(getpid()); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_NE(ns_of(holder), ns_of(getpid()));
  Supervised s("  netns: /proc/" + std::to_string(holder) + "/ns/net\n");
  s.host->start();
  const int pid = s.wait_pid();
  ASSERT_GT(pid, 0) << s.lines();
  EXPECT_EQ(ns_of(pid), ns_of(holder));
  EXPECT_NE(ns_of(pid), ns_of(getpid()));
}

// Stopping the host stops plchmi (SIGTERM) and reaps it: no process, no
// zombie left.
TEST(HmiSupervisedRealTime, StoppingTheHostReapsTheBridge) {
  Supervised s;
  s.host->start();
  const int pid = s.wait_pid();
  ASSERT_GT(pid, 0);
  s.host->stop();
  EXPECT_EQ(kill(pid, 0), -1);
  EXPECT_EQ(errno, ESRCH);
  EXPECT_EQ(waitpid(pid, nullptr, WNOHANG), -1);  // not our child any more: reaped
  EXPECT_EQ(s.host->bridge_pid(), 0);
}

// The keys' errors at their line (docs/config.md, hmi: user, netns).
TEST(HmiConfig, UserAndNetnsErrorsAreLocated) {
  const std::string base = plctest::demo_yaml();
  auto error_of = [&](const std::string& hmi) -> std::string {
    try {
      const CellConfig cfg = parse_cell_config(base + "\nhmi:\n  url: memq://\n" + hmi, "x.yaml");
      hmi::Host host(cfg.hmi, cfg.file, hmi::Host::Options{});
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  };
  const int line = int(std::count(base.begin(), base.end(), '\n')) + 4;
  const std::string at = "x.yaml:" + std::to_string(line) + ":";
  std::string e = error_of("  user: no-such-user-here\n");
  EXPECT_NE(e.find(at), std::string::npos) << e;
  EXPECT_NE(e.find("no user 'no-such-user-here'"), std::string::npos) << e;
  e = error_of("  netns: a/b\n");
  EXPECT_NE(e.find("neither a name of `ip netns list` nor an absolute path"), std::string::npos)
      << e;
  if (geteuid() == 0) {
    e = error_of("  netns: no-such-namespace-here\n");
    EXPECT_NE(e.find(at), std::string::npos) << e;
    EXPECT_NE(e.find("/var/run/netns/no-such-namespace-here"), std::string::npos) << e;
  }
}

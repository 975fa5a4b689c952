// plcrun (real time) and plcctl as separate processes over udpm:// with
// ttl=0 (issue 13, acceptance), inside a network namespace this test makes
// (`unshare --net`: its own loopback, brought up, with a multicast route),
// so the host's interfaces and routes are never touched. lcm-logger records
// the session; the test decodes that log with the generated types.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>
#include <map>
#include <sstream>

#include "hmi_test_cell.hpp"
#include "loopback_netns.hpp"
#include "plc/hmi/utime.hpp"
#include "runtime/test_helpers.hpp"
#include "softplc_hmi/cell_description_t.hpp"
#include "softplc_hmi/values_t.hpp"
#include "udpm_test_socket.hpp"

namespace {

using plctest::read_file;

plctest::RunResult sh(const std::string& cmd) { return plctest::run_command(cmd); }

// time_ns -> Tank.level from the cell's own trace (time_ns,cycle,Tank.level,...).
// `gaps` counts rows whose cycle does not follow the previous row's: the
// trace must hold every scan between its first and its last row.
std::map<std::int64_t, std::string> trace_levels(const std::string& csv, int* gaps = nullptr) {
  std::map<std::int64_t, std::string> m;
  long long last_cycle = -1;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  for (int i = 0; i < 1'000'000 && std::getline(in, line); ++i) {
    std::istringstream row(line);
    std::string t, cycle, level;
    std::getline(row, t, ',');
    std::getline(row, cycle, ',');
    std::getline(row, level, ',');
    m[std::stoll(t)] = level;
    const long long c = std::stoll(cycle);
    if (gaps && last_cycle >= 0 && c != last_cycle + 1) ++*gaps;
    last_cycle = c;
  }
  return m;
}

// The demo cell without its watchdog (on a loaded machine, ctest -j2
// beside other jobs, a first real-time scan may take tens of ms, and these
// tests are about the bridge, not the watchdog), with `hmi` appended.
std::string realtime_demo_cell(const std::string& hmi) {
  std::string cell = plctest::demo_yaml();
  const auto wd = cell.find("watchdog: 10");
  EXPECT_NE(wd, std::string::npos);
  if (wd != std::string::npos) cell.replace(wd, 12, "watchdog: 0 ");
  return cell + hmi;
}

}  // namespace

TEST(HmiUdpmRealTime, PlcctlWatchesWritesAndIsRefusedAcrossProcesses) {
  if (sh("unshare --net true").exit_code != 0)
    GTEST_SKIP() << "network namespaces are not available here (unshare --net needs root or "
                    "user namespaces); the udpm test runs only inside its own namespace";
  const std::string dir = ::testing::TempDir() + "hmi_udpm_" + std::to_string(::getpid());
  ASSERT_EQ(sh("rm -rf " + dir + " && mkdir -p " + dir).exit_code, 0);
  std::ofstream(dir + "/cell.yaml") << realtime_demo_cell(R"(
hmi:
  url: udpm://239.255.76.67:7667?ttl=0
  rate: 50
  publish: ["Tank.*"]
  writable: ["Tank.high_level"]
)");
  const std::string bin = plctest::bin_dir();
  // Every wait is bounded: plcrun runs 45 s at most (the script stops it
  // when done: a shorter span would be a window that a loaded machine's
  // slow start could miss), each plcctl call has a timeout, the poll for
  // the bridge tries 100 times (20 s), the whole script has 60 s.
  const std::string script =
      R"(
set -u
cd )" +
      dir + R"(
ip link set lo up && ip route add 224.0.0.0/4 dev lo || exit 90
lcm-logger -f -q session.lcm > logger.out 2>&1 & LOGGER=$!
)" + bin +
      R"(/plcrun cell.yaml --realtime --for 45s --trace trace.csv --trace-vars Tank.level,Tank.high_level > plcrun.out 2>&1 & PLC=$!
up=0
for i in $(seq 1 100); do
  if )" +
      bin + R"(/plcctl --timeout 200 read Tank.level > /dev/null 2>&1; then up=1; break; fi
done
[ $up = 1 ] || { kill $PLC $LOGGER; exit 91; }
)" + bin +
      R"(/plcctl watch Tank.level --count 30 --for 15s > watch.txt; echo "watch=$?"
)" + bin +
      R"(/plcctl write Tank.high_level 900; echo "write=$?"
)" + bin +
      R"(/plcctl write Tank.step 3; echo "write_refused=$?"
)" + bin +
      R"(/plcctl read Tank.high_level; echo "read=$?"
)" + bin +
      R"(/plcctl stats; echo "stats=$?"
kill -TERM $PLC; wait $PLC; echo "plcrun=$?"
kill -INT $LOGGER; wait $LOGGER
)";
  std::ofstream(dir + "/run.sh") << script;
  const auto r = sh("timeout 60 unshare --net sh " + dir + "/run.sh");
  ASSERT_NE(r.exit_code, 90) << "could not set up loopback multicast in the namespace\n"
                             << r.output;
  ASSERT_NE(r.exit_code, 91) << "the bridge never answered\n"
                             << r.output << read_file(dir + "/plcrun.out");
  EXPECT_NE(r.output.find("watch=0"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("write=0"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("write_refused=1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("not allowed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Tank.high_level = 900"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("refused 1"), std::string::npos) << r.output;  // plcctl stats

  // Watched values match the cell's own trace at the same scan (PLC time).
  // The trace holds every scan from `trace start` to `trace stop`, which in
  // an HMI run come after the cell's first scans and before its last ones
  // (the real-time cell runs from the debugger's start; the bridge publishes
  // from its first scan until it stops, after `trace stop`): values of
  // scans outside the trace's span have no row to compare with, and are
  // skipped; inside it, every one must have its row.
  int gaps = 0;
  const auto trace = trace_levels(read_file(dir + "/trace.csv"), &gaps);
  ASSERT_GT(trace.size(), 100U) << read_file(dir + "/plcrun.out");
  EXPECT_EQ(gaps, 0) << "the trace misses scans";
  const std::int64_t first_row = trace.begin()->first, last_row = trace.rbegin()->first;
  auto in_trace_span = [&](std::int64_t ns) { return ns >= first_row && ns <= last_row; };
  std::istringstream watch(read_file(dir + "/watch.txt"));
  std::string line;
  int matched = 0;
  for (int i = 0; i < 1000 && std::getline(watch, line); ++i) {
    double t = 0;
    char path[64], value[64];
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf %63s = %63s", &t, path, value), 3) << line;
    const auto ns = std::int64_t(t * 1e9 + 0.5);
    if (!in_trace_span(ns)) continue;
    auto it = trace.find(ns);
    ASSERT_NE(it, trace.end()) << "no trace row at " << ns << " ns: " << line;
    EXPECT_EQ(it->second, value) << line;
    ++matched;
  }
  EXPECT_GE(matched, 20);
  // The write reached the cell: the trace shows 900 from some scan on.
  EXPECT_NE(read_file(dir + "/trace.csv").find(",900"), std::string::npos);

  // lcm-logger's log decodes with the generated types; its values agree
  // with the trace too.
  lcm::LogFile log(dir + "/session.lcm", "r");
  ASSERT_TRUE(log.good());
  int values = 0, levels = 0, level_index = -1;
  for (int i = 0; i < 100000; ++i) {
    const lcm::LogEvent* e = log.readNextEvent();
    if (!e) break;
    if (e->channel == "PLC_DESC") {  // plcctl watch asked for it
      softplc_hmi::cell_description_t d;
      ASSERT_GE(d.decode(e->data, 0, e->datalen), 0);
      for (int k = 0; k < d.n; ++k)
        if (d.vars[std::size_t(k)].path == "Tank.level") level_index = k;
    }
    if (e->channel != "PLC_VALUES") continue;
    softplc_hmi::values_t m;
    ASSERT_GE(m.decode(e->data, 0, e->datalen), 0);
    EXPECT_EQ(m.cell, "demo");
    EXPECT_EQ(m.task, "fast");
    if (!in_trace_span(m.plc_time_ns)) continue;
    ++values;
    auto it = trace.find(m.plc_time_ns);
    ASSERT_NE(it, trace.end()) << "a snapshot of a scan the trace does not have";
    for (const auto& v : m.values)
      if (v.index == level_index && level_index >= 0) {
        EXPECT_EQ(v.text, it->second) << "at " << m.plc_time_ns << " ns";
        ++levels;
      }
  }
  EXPECT_GT(values, 10);
  EXPECT_GT(levels, 10);
}

// `plcctl watch` on a terminal redraws its block in place (cursor up over
// the block, each line cleared: ESC[nA, ESC[K); piped, it prints plain
// `time path = value` lines without any escape sequence. The terminal is a
// pseudo-terminal from util-linux `script`; plcrun and plcctl talk over udpm
// ttl=0 in the test's own network namespace, every wait bounded.
TEST(HmiUdpmRealTime, WatchRedrawsInPlaceOnATerminalAndPrintsPlainLinesWhenPiped) {
  if (sh("unshare --net true").exit_code != 0)
    GTEST_SKIP() << "network namespaces are not available here";
  if (sh("script --version").exit_code != 0) GTEST_SKIP() << "util-linux script is not installed";
  const std::string dir = ::testing::TempDir() + "hmi_tty_" + std::to_string(::getpid());
  ASSERT_EQ(sh("rm -rf " + dir + " && mkdir -p " + dir).exit_code, 0);
  std::ofstream(dir + "/cell.yaml") << realtime_demo_cell(R"(
hmi:
  url: udpm://239.255.76.67:7667?ttl=0
  rate: 50
  publish: ["Tank.*"]
)");
  const std::string bin = plctest::bin_dir();
  const std::string watch = bin + "/plcctl watch Tank.level Tank.step --count 6 --for 5s";
  std::ofstream(dir + "/run.sh") << "set -u\ncd " << dir << R"(
ip link set lo up && ip route add 224.0.0.0/4 dev lo || exit 90
)" << bin << R"(/plcrun cell.yaml --realtime --for 45s > plcrun.out 2>&1 & PLC=$!
up=0
for i in $(seq 1 100); do
  if )" << bin << R"(/plcctl --timeout 200 read Tank.level > /dev/null 2>&1; then up=1; break; fi
done
[ $up = 1 ] || { kill $PLC; exit 91; }
script -q -e -c ")" << watch << R"(" tty.out < /dev/null > /dev/null; echo "tty=$?"
)" << watch << R"( | cat > piped.out; echo "piped=$?"
kill -TERM $PLC; wait $PLC
)";
  const auto r = sh("timeout 60 unshare --net sh " + dir + "/run.sh");
  ASSERT_NE(r.exit_code, 90) << r.output;
  ASSERT_NE(r.exit_code, 91) << "the bridge never answered\n"
                             << r.output << read_file(dir + "/plcrun.out");
  EXPECT_NE(r.output.find("tty=0"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("piped=0"), std::string::npos) << r.output;

  // The terminal: a header and two variables, so each redraw after the
  // first moves the cursor up 3 lines and clears every line it rewrites.
  const std::string tty = read_file(dir + "/tty.out");
  auto count = [](const std::string& s, const std::string& what) {
    std::size_t n = 0;
    for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + what.size())) ++n;
    return n;
  };
  EXPECT_GE(count(tty, "\033[3A"), 5U) << tty;     // 6 updates: 5 redraws in place
  EXPECT_GE(count(tty, "\033[K"), 6U * 3) << tty;  // every line cleared as it is drawn
  EXPECT_NE(tty.find("Tank.level"), std::string::npos) << tty;

  // Piped: plain lines only.
  const std::string piped = read_file(dir + "/piped.out");
  EXPECT_EQ(piped.find('\033'), std::string::npos) << piped;
  std::istringstream in(piped);
  std::string line;
  int lines = 0;
  for (int i = 0; i < 1000 && std::getline(in, line); ++i) {
    double t = 0;
    char path[64], value[64];
    EXPECT_EQ(std::sscanf(line.c_str(), "%lf %63s = %63s", &t, path, value), 3) << line;
    ++lines;
  }
  EXPECT_GE(lines, 6);
}

namespace {

// A command in the test's namespace, running on; its output (stdout and
// stderr) is read line by line, and its exit status is printed last as
// "<name>=<status>" (128 + signal when a signal ended it).
struct Running {
  std::FILE* out = nullptr;
  Running(const plctest::LoopbackNetns& ns, const std::string& name, const std::string& cmd)
      : out(::popen((ns.exec() + cmd + " 2>&1; echo " + name + "=$?").c_str(), "r")) {}
  ~Running() {
    if (out) ::pclose(out);
  }
  // The next line, or nullopt at the end (bounded by the command's own --for).
  std::optional<std::string> line() {
    char b[512];
    if (!out || !std::fgets(b, sizeof b, out)) return std::nullopt;
    return std::string(b);
  }
  std::string rest() {
    std::string all;
    for (int i = 0; i < 100000; ++i) {
      auto l = line();
      if (!l) break;
      all += *l;
    }
    return all;
  }
};

}  // namespace

// Issue 22's acceptance, as processes: the 60-byte wrapping-offset fragment
// and the other hostile datagrams (hostile_set) sent three times to a
// running plcrun's command channel and to the value and trace channels of a
// running `plcctl watch` and `plcctl log`. All three keep running: watch
// prints values sent after the last burst, log records them (and none of
// the hostile bytes), plcrun answers `plcctl read` and counts the datagrams
// (`plcctl stats`: "transport: ... bad_fragment N"), and each ends with 0.
// With liblcm 1.3.1's receive path all three died with SIGSEGV at the first
// burst. In a network namespace of the test's own, every wait bounded
// (plcrun --for 8s, plcctl --for/--timeout).
TEST(HmiUdpmRealTime, HostileDatagramsLeavePlcrunAndPlcctlRunning) {
  std::string why;
  auto ns = plctest::LoopbackNetns::create(why);
  if (!ns) GTEST_SKIP() << "network namespaces unavailable, test skipped: " << why;
  const std::string dir = ::testing::TempDir() + "hmi_hostile_" + std::to_string(::getpid());
  ASSERT_EQ(sh("rm -rf " + dir + " && mkdir -p " + dir).exit_code, 0);
  std::ofstream(dir + "/cell.yaml") << realtime_demo_cell(R"(
hmi:
  url: udpm://239.255.76.67:7667?ttl=0
  rate: 50
  publish: ["Tank.*"]
)");
  const std::string bin = plctest::bin_dir();
  Running plcrun(*ns, "plcrun", bin + "/plcrun " + dir + "/cell.yaml --realtime --for 8s");
  bool up = false;
  for (int i = 0; i < 40 && !up; ++i)
    up = sh(ns->exec() + bin + "/plcctl --timeout 200 read Tank.level").exit_code == 0;
  ASSERT_TRUE(up) << "the bridge never answered\n" << plcrun.rest();
  Running log(*ns, "log", bin + "/plcctl log " + dir + "/session.lcm --for 4s");
  Running watch(*ns, "watch", bin + "/plcctl watch Tank.level --count 60 --for 5s");
  auto tx =
      ns->in([] { return std::make_unique<plctest::udpm::GroupSocket>(0xEFFF4C43, 7667, false); });
  std::size_t bursts = 0;
  auto burst = [&] {
    for (const std::string channel : {"PLC_CMD", "PLC_VALUES", "PLC_TRACE"})
      for (const auto& [d, reason] : plctest::udpm::hostile_set(channel)) tx->send(d);
    ++bursts;
  };
  // Bursts after watch's 1st, 10th and 20th line (log started before
  // watch: by then it has long subscribed); then lines until watch ends.
  int lines = 0, after_last = 0;
  std::string watched;
  std::int64_t last_burst_us = 0;
  for (int i = 0; i < 200; ++i) {
    const auto l = watch.line();
    if (!l) break;
    watched += *l;
    if (l->rfind("watch=", 0) == 0) break;
    ++lines;
    if (bursts < 3 && (lines == 1 || lines == 10 || lines == 20)) {
      burst();
      last_burst_us = plc::hmi::utime_now();
      after_last = 0;
    } else {
      ++after_last;
    }
  }
  EXPECT_EQ(bursts, 3U) << watched;
  EXPECT_GE(after_last, 10) << "watch printed too little after the last burst:\n" << watched;
  EXPECT_NE(watched.find("watch=0"), std::string::npos) << watched;
  const auto read = sh(ns->exec() + bin + "/plcctl --timeout 2000 read Tank.level");
  EXPECT_EQ(read.exit_code, 0) << read.output;
  const auto stats = sh(ns->exec() + bin + "/plcctl --timeout 3000 stats");
  EXPECT_EQ(stats.exit_code, 0) << stats.output;
  // The bridge reads every datagram to the group: 3 bursts x 3 channels x 3 bad fragments.
  EXPECT_NE(stats.output.find("bad_fragment 27"), std::string::npos) << stats.output;
  const std::string logged = log.rest();
  EXPECT_NE(logged.find("log=0"), std::string::npos) << logged;
  const std::string ran = plcrun.rest();
  EXPECT_NE(ran.find("plcrun=0"), std::string::npos) << ran;

  // The log: values recorded after the last burst, every event a message
  // the bridge sent (it decodes as its channel's type), no hostile bytes.
  lcm::LogFile f(dir + "/session.lcm", "r");
  ASSERT_TRUE(f.good());
  int values_after = 0, events = 0;
  for (int i = 0; i < 100000; ++i) {
    const lcm::LogEvent* e = f.readNextEvent();
    if (!e) break;
    ++events;
    if (e->channel == "PLC_VALUES") {
      softplc_hmi::values_t m;
      EXPECT_TRUE(plc::hmi::checked_decode(e->data, std::size_t(e->datalen), m));
      values_after += e->timestamp > last_burst_us;
    } else if (e->channel == "PLC_TRACE") {
      softplc_hmi::trace_sample_t m;
      EXPECT_TRUE(plc::hmi::checked_decode(e->data, std::size_t(e->datalen), m));
    }
  }
  EXPECT_GT(events, 20);
  EXPECT_GT(values_after, 5);
}

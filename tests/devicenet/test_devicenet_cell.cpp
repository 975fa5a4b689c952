// Integration: plcrun with the DeviceNet scanner and build/bin/dnslave (the
// PR5510 behind its PR1721/34 card) as separate processes on one CAN-over-
// UDP bus (hub in plcrun), the filling cell's batch weighing running over
// it in real time. The slave is killed mid-run (SIGKILL) and started again:
// the scanner reports the loss within the connection timeout, the weighing
// blocks report DeviceOffline, the cell's outputs go safe (conveyor power
// off), and after the restart the scanner allocates again and the cell
// goes on filling. The bus is captured to pcap and decoded by tshark's
// DeviceNet dissector: no malformed frames.
//
// Waiting is on events: lines the processes print (read with poll(),
// bounded by a deadline). The one timed wait is the scenario's own: let
// the cell fill for a few seconds before pulling the plug.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "runtime/test_helpers.hpp"

extern char** environ;

namespace {

std::int64_t mono_ms() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t(ts.tv_sec) * 1000 + ts.tv_nsec / 1'000'000;
}

// A child process with its stdout+stderr on a pipe we read line by line.
struct Child {
  pid_t pid = -1;
  int fd = -1;
  std::string buffer, all;

  Child(const std::vector<std::string>& args) {
    int p[2];
    if (pipe(p) != 0) return;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, p[1], 1);
    posix_spawn_file_actions_adddup2(&fa, p[1], 2);
    posix_spawn_file_actions_addclose(&fa, p[0]);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    if (posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&fa);
    close(p[1]);
    fd = p[0];
  }
  ~Child() {
    if (pid > 0) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
    if (fd >= 0) close(fd);
  }
  // Reads until a line containing `text` arrives (true) or the deadline.
  bool wait_for(const std::string& text, int timeout_ms) {
    const std::int64_t end = mono_ms() + timeout_ms;
    for (int guard = 0; guard < 100000; ++guard) {
      const auto nl = buffer.find(text);
      if (nl != std::string::npos) {
        buffer.erase(0, nl + text.size());
        return true;
      }
      const std::int64_t left = end - mono_ms();
      if (left <= 0) return false;
      pollfd p{fd, POLLIN, 0};
      if (poll(&p, 1, static_cast<int>(left)) <= 0) continue;
      char b[4096];
      const ssize_t n = read(fd, b, sizeof b);
      if (n <= 0) return false;  // the process ended
      buffer.append(b, static_cast<std::size_t>(n));
      all.append(b, static_cast<std::size_t>(n));
    }
    return false;
  }
  // Reads everything until the process exits; returns its exit code.
  int finish(int timeout_ms) {
    wait_for("\x01never\x01", timeout_ms);
    int status = 0;
    if (waitpid(pid, &status, 0) == pid) pid = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  void kill_now() {
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    pid = -1;
  }
};

std::uint16_t free_udp_port() {
  const int s = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
  close(s);
  return ntohs(a.sin_port);
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (auto p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

struct Row {
  std::int64_t t_ns;
  std::map<std::string, std::string> v;
};

std::vector<Row> read_trace(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> head;
  std::vector<Row> rows;
  for (int n = 0; n < 10'000'000 && std::getline(in, line); ++n) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (head.empty()) {
      head = cells;
      continue;
    }
    Row r{std::stoll(cells.at(0)), {}};
    for (std::size_t i = 2; i < cells.size() && i < head.size(); ++i) r.v[head[i]] = cells[i];
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace

TEST(DeviceNetCell, BatchWeighingOverDeviceNetSurvivesASlaveKillAndRestart) {
  const std::string port = std::to_string(free_udp_port());
  const std::string pcap = plctest::temp_path("dnet_cell.pcap");
  const std::string trace = plctest::temp_path("dnet_cell.csv");
  std::string cell = plctest::read_file(plctest::source_path("programs/filling_cell/cell_devicenet.yaml"));
  ASSERT_FALSE(cell.empty());
  cell = replace_all(cell, "udp:127.0.0.1:47800", "udp:127.0.0.1:" + port);
  cell = replace_all(cell, "      poll_cycle: 10ms",
                     "      poll_cycle: 10ms\n      pcap: \"" + pcap + "\"");
  cell = replace_all(cell, "      scale.BusType: 1",
                     "      target_kg: 5.0\n      scale.BusType: 1");
  const std::string cell_file = plctest::write_temp("dnet_cell.yaml", cell);
  std::string slave = plctest::read_file(plctest::source_path("programs/filling_cell/dnslave.yaml"));
  slave = replace_all(slave, "udp:127.0.0.1:47800", "udp:127.0.0.1:" + port);
  const std::string slave_file = plctest::write_temp("dnet_slave.yaml", slave);

  Child plc({plctest::plcrun_path(), cell_file, "--realtime", "--for", "30s", "-q", "--trace",
             trace, "--trace-vars",
             "Cell.scale.Online,Cell.step,Cell.containers,Cell.power.Enable,Cell.dose.Error,"
             "Cell.dose.ErrorID",
             "--print-vars", "Cell.containers"});
  ASSERT_GT(plc.pid, 0);
  const std::string dnslave = plctest::bin_dir() + "/dnslave";
  auto slave1 = std::make_unique<Child>(std::vector<std::string>{dnslave, slave_file});
  ASSERT_TRUE(plc.wait_for("scale (MAC 5): online", 15000)) << plc.all;

  // Fill for a while, then pull the plug.
  plc.wait_for("\x01never\x01", 7000);
  slave1->kill_now();
  ASSERT_TRUE(plc.wait_for("scale (MAC 5): lost: connection timed out", 5000)) << plc.all;
  auto slave2 = std::make_unique<Child>(std::vector<std::string>{dnslave, slave_file});
  ASSERT_TRUE(plc.wait_for("scale (MAC 5): online", 15000)) << plc.all;
  ASSERT_EQ(plc.finish(40000), 0) << plc.all;
  slave2.reset();

  // The scanner's own measure: lost after 4 x EPR (200 ms) of silence.
  const auto at = plc.all.find("no valid poll response for ");
  ASSERT_NE(at, std::string::npos);
  const int silent_ms = std::stoi(plc.all.substr(at + 27));
  EXPECT_GE(silent_ms, 200);
  EXPECT_LE(silent_ms, 200 + 20) << "declared lost within the 4 x EPR timeout (+ 2 bus-thread wake-ups)";

  const auto rows = read_trace(trace);
  ASSERT_GT(rows.size(), 1000u);
  // The loss in the trace: Online TRUE -> FALSE -> TRUE.
  std::size_t lost = 0, back = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (!lost && rows[i - 1].v.at("Cell.scale.Online") == "TRUE" &&
        rows[i].v.at("Cell.scale.Online") == "FALSE")
      lost = i;
    if (lost && !back && rows[i].v.at("Cell.scale.Online") == "TRUE") back = i;
  }
  ASSERT_GT(lost, 0u);
  ASSERT_GT(back, lost);
  const int before = std::stoi(rows[lost].v.at("Cell.containers"));
  EXPECT_GE(before, 1) << "containers filled before the kill";
  // While the scale is away: the dose block reports DeviceOffline (0x8003)
  // at once, the cell stops the conveyor (power Enable FALSE).
  bool reported = false, safe = false;
  for (std::size_t i = lost; i < back; ++i) {
    reported = reported || rows[i].v.at("Cell.dose.ErrorID") == "16#8003";
    if (i > lost + 5) safe = rows[i].v.at("Cell.power.Enable") == "FALSE";
    if (i > lost + 5 && !safe) break;
  }
  EXPECT_TRUE(reported);
  EXPECT_TRUE(safe) << "conveyor power stays off while the scale is lost";
  const int after = std::stoi(rows.back().v.at("Cell.containers"));
  EXPECT_GT(after, before) << "the cell goes on filling after the restart";

  // tshark's DeviceNet dissector (Wireshark 4.0) over the capture.
  if (plctest::run_command("tshark --version").exit_code != 0)
    GTEST_SKIP() << "tshark not installed (scripts/setup installs it)";
  const auto t = plctest::run_command("tshark -n -r " + pcap + " -d 'can.subdissector,devicenet'");
  ASSERT_EQ(t.exit_code, 0) << t.output.substr(0, 2000);
  EXPECT_EQ(t.output.find("Malformed"), std::string::npos) << t.output.substr(0, 4000);
  EXPECT_NE(t.output.find("Poll"), std::string::npos) << t.output.substr(0, 2000);
  EXPECT_NE(t.output.find("Unconnected"), std::string::npos) << t.output.substr(0, 2000);
}

// Child processes for the process-level DeviceNet tests (plcrun, dnslave):
// output read line by line with poll() up to a deadline, never a sleep.
#pragma once

#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cstdint>
#include <string>
#include <vector>

extern char** environ;

namespace dntest {

inline std::int64_t mono_ms() {
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

inline std::uint16_t free_udp_port() {
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

}  // namespace dntest

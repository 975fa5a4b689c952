// Starts plchmi, watches it and starts it again when it dies, with backoff
// (hmi-bridge/README.md, "Process layout"). Runs on the HMI host's thread,
// never on a scan thread.
//
// The child is made with clone(CLONE_VM | CLONE_VFORK), as posix_spawn
// does: no copy of plcrun's page tables, so no copy-on-write faults in the
// scan threads while the child gets to exec (fork() of a large real-time
// process would give them). Between clone and exec the child makes system
// calls only: signal dispositions back to default; setns() into the
// configured network namespace; the shared-memory descriptors and the
// doorbell moved to 3, 4, 5 and every other descriptor closed (plchmi
// never holds a descriptor of the cell's files); when plcrun is root, the
// capability bounding set dropped, then setgroups/setresgid/setresuid to
// the configured user; PR_SET_NO_NEW_PRIVS, no ambient and no remaining
// capability; PR_SET_PDEATHSIG (SIGKILL when plcrun's host thread goes);
// the signal mask restored; execve with a short environment.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace plc::hmi {

class Supervisor {
 public:
  using Clock = std::chrono::steady_clock;
  struct Backoff {
    std::chrono::milliseconds first{500};           // after the first crash
    std::chrono::milliseconds max{30'000};          // doubling up to this
    std::chrono::milliseconds reset_after{60'000};  // up this long: back to `first`
  };
  struct Spawn {
    std::string exe;
    std::vector<std::string> args;  // after argv[0]
    std::vector<int> fds;           // become 3, 4, 5, ... in the child
    int netns_fd = -1;              // setns() into it first (-1: stay)
    bool change_user = false;       // plcrun is root: drop to uid/gid
    uid_t uid = 0;
    gid_t gid = 0;
  };
  struct Event {
    enum class Kind { Started, Exited, StartFailed } kind;
    std::string text;                         // Exited: "exited (signal 11)"; StartFailed: why
    std::chrono::milliseconds restart_in{0};  // Exited, StartFailed: the next try
    Clock::duration up_for{};                 // Exited: how long it ran
  };

  Supervisor(Spawn spawn, Backoff backoff);
  ~Supervisor();
  Supervisor(const Supervisor&) = delete;
  Supervisor& operator=(const Supervisor&) = delete;

  // Starts it now (the first time) or when the backoff says; reaps it when
  // it exited. Returns what happened since the last call.
  std::vector<Event> poll(Clock::time_point now);
  // Readable when the child has exited (poll(2) on it; -1 while none runs).
  [[nodiscard]] int pidfd() const { return pidfd_; }
  [[nodiscard]] pid_t pid() const { return pid_.load(); }
  // When poll() should next be called at the latest (a restart due).
  [[nodiscard]] std::optional<Clock::time_point> next_start() const;
  // SIGTERM, then SIGKILL after `grace`, and reaped. No restart afterwards.
  void stop(std::chrono::milliseconds grace = std::chrono::milliseconds(2000));
  // How many times it was started.
  [[nodiscard]] std::uint64_t starts() const { return starts_; }

  // "exited with status 3", "exited (signal 11)" for a wait status.
  static std::string describe(int wait_status);

 private:
  // Starts the child; the reason when it could not.
  std::string start();

  Spawn spawn_;
  Backoff backoff_;
  // Written by the host's thread, read by others (Host::bridge_pid()).
  std::atomic<pid_t> pid_{0};
  int pidfd_ = -1;
  bool stopped_ = false;
  std::uint64_t starts_ = 0;
  std::chrono::milliseconds delay_{0};
  std::optional<Clock::time_point> due_;  // next start
  Clock::time_point started_at_{};
};

}  // namespace plc::hmi

#include "plc/hmi/supervisor.hpp"

#include <fcntl.h>
#include <linux/capability.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <system_error>
#include <thread>

// ThreadSanitizer intercepts clone() as a fork and fails its own check on a
// child that shares the memory (CLONE_VM). A TSan build starts plchmi with
// fork() instead, and the child reports a failed step through a pipe: the
// same steps, the same messages; only the copy of the address space that
// clone avoids (plcrun's scan threads' copy-on-write faults) comes back,
// which a TSan build does not measure.
#if defined(__SANITIZE_THREAD__)
#define PLC_SUPERVISOR_FORK 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define PLC_SUPERVISOR_FORK 1
#endif
#endif

namespace plc::hmi {

namespace {

// The fork path's report descriptor in the child (kept out of the range
// the child closes, close-on-exec like the pipe it copies).
constexpr int kReportFd = 1000;

// What the child needs, prepared by the parent: between clone and exec the
// child only makes system calls (no allocation, no lock, no glibc wrapper
// that talks to other threads).
struct ChildArgs {
  const char* exe = nullptr;
  char* const* argv = nullptr;
  char* const* envp = nullptr;
  int fds[8] = {};
  int nfds = 0;
  int netns_fd = -1;
  bool change_user = false;
  uid_t uid = 0;
  gid_t gid = 0;
  pid_t parent = 0;
  sigset_t mask{};
  // Written by the child when it fails (the memory is shared until exec;
  // in the fork path also written to report_fd).
  volatile int failed_step = 0;
  volatile int failed_errno = 0;
  int report_fd = -1;
};

constexpr const char* kSteps[] = {"",
                                  "sigaction",
                                  "setns into the network namespace",
                                  "moving the shared-memory descriptors",
                                  "closing the other descriptors",
                                  "dropping the capability bounding set",
                                  "setgroups",
                                  "setresgid",
                                  "setresuid",
                                  "PR_SET_NO_NEW_PRIVS",
                                  "clearing ambient capabilities",
                                  "capset",
                                  "PR_SET_PDEATHSIG",
                                  "plcrun ended",
                                  "execve"};

int child_main(void* p) {
  auto* a = static_cast<ChildArgs*>(p);
  auto fail = [a](int step) {
    a->failed_errno = errno;
    a->failed_step = step;
    if (a->report_fd >= 0) {
      const int report[2] = {step, a->failed_errno};
      (void)!write(a->report_fd, report, sizeof report);
    }
    _exit(127);
  };
  if (a->report_fd >= 0) {
    if (dup3(a->report_fd, kReportFd, O_CLOEXEC) != kReportFd) _exit(127);
    a->report_fd = kReportFd;
  }
  // Handlers are plcrun's code: none may run in the child.
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  for (int s = 1; s < NSIG; ++s)
    if (s != SIGKILL && s != SIGSTOP) sigaction(s, &dfl, nullptr);  // glibc's own: EINVAL
  if (a->netns_fd >= 0 && setns(a->netns_fd, CLONE_NEWNET) != 0) fail(2);
  // Out of the way of the targets 3.. first (they are close-on-exec).
  int high[8];
  for (int i = 0; i < a->nfds; ++i) {
    high[i] = fcntl(a->fds[i], F_DUPFD_CLOEXEC, 100);
    if (high[i] < 0) fail(3);
  }
  for (int i = 0; i < a->nfds; ++i)
    if (dup2(high[i], 3 + i) != 3 + i) fail(3);
  if (a->report_fd < 0) {
    if (syscall(SYS_close_range, 3 + a->nfds, ~0U, 0) != 0) fail(4);
  } else if (syscall(SYS_close_range, 3 + a->nfds, kReportFd - 1, 0) != 0 ||
             syscall(SYS_close_range, kReportFd + 1, ~0U, 0) != 0) {
    fail(4);
  }
  if (a->change_user) {
    // The bounding set first: dropping it needs CAP_SETPCAP, which setuid takes.
    for (int cap = 0; cap <= 63; ++cap)
      if (prctl(PR_CAPBSET_DROP, cap, 0, 0, 0) != 0 && errno != EINVAL) fail(5);
    // Raw system calls: glibc's wrappers would signal plcrun's threads
    // (they set the ids of every thread of what they take for this process).
    const gid_t groups[1] = {a->gid};
    if (syscall(SYS_setgroups, 1, groups) != 0) fail(6);
    if (syscall(SYS_setresgid, a->gid, a->gid, a->gid) != 0) fail(7);
    if (syscall(SYS_setresuid, a->uid, a->uid, a->uid) != 0) fail(8);
  }
  if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0) fail(9);
  if (prctl(PR_CAP_AMBIENT, PR_CAP_AMBIENT_CLEAR_ALL, 0, 0, 0) != 0 && errno != EINVAL) fail(10);
  __user_cap_header_struct hdr{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct none[2] = {};
  if (syscall(SYS_capset, &hdr, none) != 0) fail(11);
  // After setresuid, which clears it.
  if (prctl(PR_SET_PDEATHSIG, SIGKILL, 0, 0, 0) != 0) fail(12);
  if (getppid() != a->parent) fail(13);
  sigprocmask(SIG_SETMASK, &a->mask, nullptr);
  execve(a->exe, a->argv, a->envp);
  fail(14);
  return 127;
}

// The environment plchmi gets: nothing of plcrun's but what sanitizers and
// the locale read.
std::vector<std::string> child_environment() {
  std::vector<std::string> env = {"PATH=/usr/local/bin:/usr/bin:/bin"};
  for (const char* name :
       {"LANG", "LC_ALL", "TZ", "ASAN_OPTIONS", "UBSAN_OPTIONS", "TSAN_OPTIONS", "LSAN_OPTIONS"})
    if (const char* v = std::getenv(name)) env.push_back(std::string(name) + "=" + v);
  return env;
}

}  // namespace

Supervisor::Supervisor(Spawn spawn, Backoff backoff)
    : spawn_(std::move(spawn)), backoff_(backoff) {}

Supervisor::~Supervisor() { stop(); }

std::string Supervisor::describe(int status) {
  if (WIFSIGNALED(status))
    return std::string("exited (signal ") + std::to_string(WTERMSIG(status)) + ", " +
           sigabbrev_np(WTERMSIG(status)) + ")";
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  return "stopped (wait status " + std::to_string(status) + ")";
}

std::string Supervisor::start() {
  if (spawn_.fds.size() > 8) return "more than 8 descriptors to pass";
  std::vector<std::string> args = {spawn_.exe};
  args.insert(args.end(), spawn_.args.begin(), spawn_.args.end());
  std::vector<char*> argv;
  for (auto& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  std::vector<std::string> env = child_environment();
  std::vector<char*> envp;
  for (auto& s : env) envp.push_back(s.data());
  envp.push_back(nullptr);

  auto a = std::make_unique<ChildArgs>();
  a->exe = spawn_.exe.c_str();
  a->argv = argv.data();
  a->envp = envp.data();
  a->nfds = int(spawn_.fds.size());
  for (int i = 0; i < a->nfds; ++i) a->fds[i] = spawn_.fds[std::size_t(i)];
  a->netns_fd = spawn_.netns_fd;
  a->change_user = spawn_.change_user;
  a->uid = spawn_.uid;
  a->gid = spawn_.gid;
  a->parent = getpid();
  // Every signal blocked from clone until the child has reset its
  // handlers (plcrun's handlers must never run in it).
  sigset_t all;
  sigfillset(&all);
  pthread_sigmask(SIG_SETMASK, &all, &a->mask);
#ifdef PLC_SUPERVISOR_FORK
  int report[2] = {-1, -1};
  if (pipe2(report, O_CLOEXEC) != 0) {
    const int e = errno;
    pthread_sigmask(SIG_SETMASK, &a->mask, nullptr);
    return std::string("pipe: ") + std::strerror(e);
  }
  a->report_fd = report[1];
  const pid_t pid = fork();
  if (pid == 0) _exit(child_main(a.get()));
  const int clone_errno = errno;
  pthread_sigmask(SIG_SETMASK, &a->mask, nullptr);
  close(report[1]);
  if (pid > 0) {
    // EOF at the child's execve (close-on-exec), or its failed step.
    int got[2] = {0, 0};
    ssize_t n = -1;
    do n = read(report[0], got, sizeof got);
    while (n < 0 && errno == EINTR);
    if (n == ssize_t(sizeof got)) {
      a->failed_step = got[0];
      a->failed_errno = got[1];
    }
  }
  close(report[0]);
  if (pid < 0) return std::string("fork: ") + std::strerror(clone_errno);
#else
  constexpr std::size_t kStack = 64 * 1024;
  auto stack = std::make_unique<unsigned char[]>(kStack);
  const pid_t pid =
      clone(child_main, stack.get() + kStack, CLONE_VM | CLONE_VFORK | SIGCHLD, a.get());
  const int clone_errno = errno;
  pthread_sigmask(SIG_SETMASK, &a->mask, nullptr);
  if (pid < 0) return std::string("clone: ") + std::strerror(clone_errno);
#endif
  if (a->failed_step) {
    int status = 0;
    waitpid(pid, &status, 0);
    const int step = std::clamp(int(a->failed_step), 0, int(std::size(kSteps)) - 1);
    return std::string(kSteps[step]) + ": " + std::strerror(a->failed_errno);
  }
  pid_ = pid;
  pidfd_ = int(syscall(SYS_pidfd_open, pid, 0));
  ++starts_;
  started_at_ = Clock::now();
  return {};
}

std::vector<Supervisor::Event> Supervisor::poll(Clock::time_point now) {
  std::vector<Event> out;
  if (stopped_) return out;
  if (pid_ > 0) {
    int status = 0;
    const pid_t r = waitpid(pid_, &status, WNOHANG);
    if (r == pid_) {
      Event e{Event::Kind::Exited, describe(status), {}, now - started_at_};
      if (pidfd_ >= 0) close(pidfd_);
      pidfd_ = -1;
      pid_ = 0;
      // Up long enough: this is a new trouble, not the same one again.
      if (e.up_for >= backoff_.reset_after || delay_.count() == 0)
        delay_ = backoff_.first;
      else
        delay_ = std::min(backoff_.max, delay_ * 2);
      e.restart_in = delay_;
      due_ = now + delay_;
      out.push_back(e);
    }
  } else if (starts_ == 0 && !due_) {
    due_ = now;  // the first start
  }
  if (pid_ == 0 && due_ && now >= *due_) {
    due_.reset();
    const std::string err = start();
    if (err.empty()) {
      out.push_back({Event::Kind::Started, {}, {}, {}});
    } else {
      delay_ = delay_.count() == 0 ? backoff_.first : std::min(backoff_.max, delay_ * 2);
      due_ = now + delay_;
      out.push_back({Event::Kind::StartFailed, err, delay_, {}});
    }
  }
  return out;
}

std::optional<Supervisor::Clock::time_point> Supervisor::next_start() const {
  if (stopped_ || pid_ > 0) return std::nullopt;
  return due_;
}

void Supervisor::stop(std::chrono::milliseconds grace) {
  stopped_ = true;
  due_.reset();
  if (pid_ <= 0) return;
  kill(pid_, SIGTERM);
  const auto deadline = Clock::now() + grace;
  int status = 0;
  bool reaped = false;
  while (!reaped) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) break;
    if (pidfd_ >= 0) {
      pollfd p{pidfd_, POLLIN, 0};
      ::poll(&p, 1, int(left.count()));
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    reaped = waitpid(pid_, &status, WNOHANG) == pid_;
  }
  if (!reaped) {
    kill(pid_, SIGKILL);
    waitpid(pid_, &status, 0);
  }
  if (pidfd_ >= 0) close(pidfd_);
  pidfd_ = -1;
  pid_ = 0;
}

}  // namespace plc::hmi

#include "loopback_netns.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "runtime/test_helpers.hpp"
#include "stale_netns.hpp"

namespace plctest {

namespace {

const char* const kPrefix = "plchmi";

}  // namespace

std::unique_ptr<LoopbackNetns> LoopbackNetns::create(std::string& why_not) {
  if (::geteuid() != 0) {
    why_not = "not root (creating a network namespace needs root)";
    return nullptr;
  }
  if (run_command("ip -V").exit_code != 0) {
    why_not = "the `ip` tool (iproute2) is missing";
    return nullptr;
  }
  delete_stale_netns(kPrefix);
  static std::atomic<int> counter{0};
  std::unique_ptr<LoopbackNetns> ns(new LoopbackNetns);
  const std::string name = kPrefix + std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const auto made = run_command("ip netns add " + name);
  if (made.exit_code != 0) {
    why_not = "`ip netns add` failed: " + made.output;
    return nullptr;
  }
  ns->name_ = name;
  for (const std::string cmd : {"link set lo up", "route add 224.0.0.0/4 dev lo"}) {
    const auto r = run_command("ip -n " + name + " " + cmd);
    if (r.exit_code != 0) {
      why_not = "`ip -n " + name + " " + cmd + "` failed: " + r.output;
      return nullptr;  // the destructor deletes it
    }
  }
  return ns;
}

LoopbackNetns::~LoopbackNetns() {
  if (!name_.empty()) (void)run_command("ip netns delete " + name_);
}

bool LoopbackNetns::enter(const std::string& ns) {
  const int fd = ::open(("/run/netns/" + ns).c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::setns(fd, CLONE_NEWNET) == 0;
  ::close(fd);
  return ok;
}

pid_t LoopbackNetns::fork_in(const std::function<int()>& f) const {
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (!enter(name_)) ::_exit(126);
    ::_exit(f());
  }
  return pid;
}

std::optional<int> wait_child(pid_t pid, std::chrono::milliseconds timeout) {
  const int pidfd = static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
  if (pidfd >= 0) {
    pollfd p{pidfd, POLLIN, 0};
    (void)::poll(&p, 1, static_cast<int>(timeout.count()));
    ::close(pidfd);
  }
  int status = 0;
  if (::waitpid(pid, &status, WNOHANG) == pid) return status;
  ::kill(pid, SIGKILL);
  (void)::waitpid(pid, &status, 0);
  return std::nullopt;
}

}  // namespace plctest

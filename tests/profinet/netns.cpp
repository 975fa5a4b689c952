#include "netns.hpp"

#include <fcntl.h>
#include <linux/if_ether.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

#include "runtime/test_helpers.hpp"
#include "stale_netns.hpp"

namespace plctest {

namespace {

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

const char* const kPrefix = "plcpn";

}  // namespace

std::unique_ptr<NetnsPair> NetnsPair::create(std::string& why_not) {
  if (::geteuid() != 0) {
    why_not = "not root (creating network namespaces and raw sockets needs root)";
    return nullptr;
  }
  if (run_command("ip -V").exit_code != 0) {
    why_not = "the `ip` tool (iproute2) is missing";
    return nullptr;
  }
  delete_stale_netns(kPrefix);
  static std::atomic<int> counter{0};
  const int n = counter++;
  std::unique_ptr<NetnsPair> p(new NetnsPair);
  const std::string base = kPrefix + std::to_string(::getpid()) + "_" + std::to_string(n);
  const std::string net = "10.88." + std::to_string(n % 250) + ".";
  p->a_ = {base + "a", "pna", net + "1"};
  p->b_ = {base + "b", "pnb", net + "2"};
  auto step = [&](const std::string& cmd) {
    const auto r = run_command(cmd);
    if (r.exit_code != 0) why_not = "`" + cmd + "` failed: " + r.output;
    return r.exit_code == 0;
  };
  const std::string A = quote(p->a_.ns), B = quote(p->b_.ns);
  if (!step("ip netns add " + A)) return nullptr;
  p->made_a_ = true;
  if (!step("ip netns add " + B)) return nullptr;
  p->made_b_ = true;
  // The pair is made inside A, its peer goes straight into B.
  if (!step("ip -n " + A + " link add pna type veth peer name pnb netns " + B) ||
      !step("ip -n " + A + " addr add " + p->a_.ip + "/24 dev pna") ||
      !step("ip -n " + B + " addr add " + p->b_.ip + "/24 dev pnb") ||
      !step("ip -n " + A + " link set lo up") || !step("ip -n " + B + " link set lo up") ||
      !step("ip -n " + A + " link set pna up") || !step("ip -n " + B + " link set pnb up"))
    return nullptr;
  // Raw sockets in the namespace (CAP_NET_RAW; a seccomp profile may deny them).
  const bool raw_ok = p->in(p->a_, [] {
    const int fd = ::socket(AF_PACKET, SOCK_RAW, 0);
    if (fd >= 0) ::close(fd);
    return fd >= 0;
  });
  if (!raw_ok) {
    why_not = "raw sockets (AF_PACKET) are not permitted here";
    return nullptr;
  }
  return p;
}

NetnsPair::~NetnsPair() {
  // Deleting a namespace deletes the veth pair with it.
  if (made_a_) (void)run_command("ip netns delete " + quote(a_.ns));
  if (made_b_) (void)run_command("ip netns delete " + quote(b_.ns));
}

NsRun NetnsPair::run(const NetnsSide& side, const std::string& cmd) const {
  const auto r = run_command("timeout 60 ip netns exec " + quote(side.ns) + " sh -c " + quote(cmd));
  return {r.exit_code, r.output};
}

std::unique_ptr<NsProcess> NetnsPair::start(const NetnsSide& side, const std::string& cmd) const {
  static std::atomic<int> counter{0};
  const std::string ns_path = "/run/netns/" + side.ns;
  const std::string log =
      ::testing::TempDir() + side.ns + "_proc" + std::to_string(counter++) + ".log";
  const std::string script = "exec " + cmd;
  const int logfd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int nsfd = ::open(ns_path.c_str(), O_RDONLY | O_CLOEXEC);
  if (logfd < 0 || nsfd < 0) {
    if (logfd >= 0) ::close(logfd);
    if (nsfd >= 0) ::close(nsfd);
    ADD_FAILURE() << "cannot start in " << side.ns << ": " << std::strerror(errno);
    return nullptr;
  }
  const pid_t pid = ::fork();
  if (pid == 0) {
    // Only async-signal-safe calls between fork and exec.
    ::setpgid(0, 0);
    if (::setns(nsfd, CLONE_NEWNET) != 0) ::_exit(126);
    ::dup2(logfd, 1);
    ::dup2(logfd, 2);
    ::execl("/bin/sh", "sh", "-c", script.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(logfd);
  ::close(nsfd);
  if (pid < 0) {
    ADD_FAILURE() << "fork: " << std::strerror(errno);
    return nullptr;
  }
  ::setpgid(pid, pid);  // also from here: no race with signal() before the child ran
  return std::make_unique<NsProcess>(pid, log);
}

NsProcess::~NsProcess() {
  if (!reaped_) {
    signal(SIGKILL);
    (void)wait(std::chrono::seconds(10));
  }
}

void NsProcess::signal(int sig) const {
  if (!reaped_) ::kill(-pid_, sig);
}

bool NsProcess::running() { return wait(std::chrono::milliseconds(0)) == -1; }

int NsProcess::wait(std::chrono::milliseconds timeout) {
  if (reaped_) return status_;
  const int pidfd = static_cast<int>(::syscall(SYS_pidfd_open, pid_, 0));
  if (pidfd >= 0) {
    pollfd p{pidfd, POLLIN, 0};
    (void)::poll(&p, 1, static_cast<int>(timeout.count()));
    ::close(pidfd);
  }
  int st = 0;
  const pid_t r = ::waitpid(pid_, &st, WNOHANG);
  if (r != pid_) return -1;
  reaped_ = true;
  status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  return status_;
}

int NsProcess::stop(std::chrono::milliseconds grace) {
  signal(SIGTERM);
  int st = wait(grace);
  if (st == -1) {
    signal(SIGKILL);
    st = wait(std::chrono::seconds(10));
  }
  return st;
}

std::string NsProcess::output() const { return read_file(log_); }

bool NetnsPair::enter(const NetnsSide& side) {
  const int fd = ::open(("/run/netns/" + side.ns).c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::setns(fd, CLONE_NEWNET) == 0;
  ::close(fd);
  return ok;
}

std::thread NetnsPair::start_in(const NetnsSide& side, std::function<void()> f) const {
  return std::thread([side, f = std::move(f)] {
    if (enter(side))
      f();
    else
      ADD_FAILURE() << "cannot enter network namespace " << side.ns;
  });
}

}  // namespace plctest

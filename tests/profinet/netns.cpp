#include "netns.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <linux/if_ether.h>
#include <sched.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

#include "runtime/test_helpers.hpp"

namespace plctest {

namespace {

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

const char* const kPrefix = "plcpn";

// Deletes namespaces "plcpn<pid>_..." of processes that no longer run.
void delete_stale() {
  DIR* d = ::opendir("/run/netns");
  if (!d) return;
  std::vector<std::string> stale;
  for (int i = 0; i < 10000; ++i) {
    dirent* e = ::readdir(d);
    if (!e) break;
    const std::string name = e->d_name;
    if (name.rfind(kPrefix, 0) != 0) continue;
    const int pid = std::atoi(name.c_str() + std::strlen(kPrefix));
    if (pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH) stale.push_back(name);
  }
  ::closedir(d);
  for (const auto& n : stale) (void)run_command("ip netns delete " + quote(n));
}

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
  delete_stale();
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

// A network namespace of the test's own for LCM over udpm://...?ttl=0: its
// loopback up and the multicast route udpm needs (224.0.0.0/4 dev lo), so
// the test's datagrams, hostile ones included, never touch the host's
// interfaces, routes or other processes. Named "plchmi<pid>_<n>"; deleted
// when it ends, and one left by a process that died is deleted the next
// time one is made (the pattern of tests/profinet/netns.hpp, one namespace
// and no veth pair).
//   in(f)       f() on a thread that entered it: sockets opened there live
//               in it and may then be used from any thread
//   fork_in(f)  a child process (fork, no exec) inside it, exit code f()
//   exec()      "ip netns exec NAME ", to run a program inside it
#pragma once

#include <sys/types.h>

#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <thread>

namespace plctest {

class LoopbackNetns {
 public:
  // nullptr and the reason when this machine cannot make one (not root, no
  // `ip`, namespaces not permitted).
  static std::unique_ptr<LoopbackNetns> create(std::string& why_not);
  ~LoopbackNetns();
  LoopbackNetns(const LoopbackNetns&) = delete;
  LoopbackNetns& operator=(const LoopbackNetns&) = delete;

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] std::string exec() const { return "ip netns exec " + name_ + " "; }

  // Runs f on a new thread that joined the namespace; returns what f
  // returns (std::future_error broken_promise if it could not join).
  template <class F>
  auto in(F f) const -> decltype(f()) {
    std::packaged_task<decltype(f())()> task(std::move(f));
    auto result = task.get_future();
    std::thread t([this, task = std::move(task)]() mutable {
      if (enter(name_)) task();
    });
    t.join();
    return result.get();
  }

  // A child process that joined the namespace and exits with f()'s value
  // (126 if it could not join). Call it while the test process has one
  // thread (fork copies only the caller).
  [[nodiscard]] pid_t fork_in(const std::function<int()>& f) const;

  // Joins the calling thread to namespace `ns`.
  static bool enter(const std::string& ns);

 private:
  LoopbackNetns() = default;
  std::string name_;
};

// The wait status of child `pid` once it ended, waiting at most `timeout`
// (pidfd + poll, no sleeping); nullopt if it still ran (it is then killed
// and reaped).
std::optional<int> wait_child(pid_t pid, std::chrono::milliseconds timeout);

}  // namespace plctest

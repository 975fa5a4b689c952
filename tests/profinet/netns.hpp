// Test fixture: two fresh network namespaces, A and B, joined by a veth pair
// (pna in A, pnb in B, created inside A with its peer put straight into B,
// so no host interface is ever made or touched), up, with 10.88.X.1/24 on
// pna and 10.88.X.2/24 on pnb. Names are unique per process and pair
// ("plcpn<pid>_<n>a"/"...b"); the namespaces are deleted when the pair ends
// (also when a test fails), and namespaces left behind by a process that
// died are deleted the next time a pair is made.
//
// A test uses it as a fixture (NetnsTest: SetUp skips the test with a clear
// message where namespaces or raw sockets are unavailable), then
//   run(a(), "cmd")        a shell command inside A (ip netns exec)
//   in(a(), [&]{ ... })    a function on a thread that entered A (setns):
//                          sockets it opens live in A, and may then be used
//                          from any thread
//   start_in(b(), f)       the same, running on while the test goes on
//   start(b(), "cmd")      a child process inside B running on while the
//                          test goes on (pndevsim against plcrun in A);
//                          killed when its handle ends
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <thread>

namespace plctest {

struct NetnsSide {
  std::string ns;     // namespace name (/run/netns/NAME)
  std::string iface;  // its end of the veth pair
  std::string ip;     // its address, "10.88.X.1" / "10.88.X.2"
};

struct NsRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// A child process in a namespace, in its own process group; stdout and
// stderr go to a log file. The destructor kills the group if it still runs.
class NsProcess {
 public:
  NsProcess(int pid, std::string log) : pid_(pid), log_(std::move(log)) {}
  ~NsProcess();
  NsProcess(const NsProcess&) = delete;
  NsProcess& operator=(const NsProcess&) = delete;

  [[nodiscard]] int pid() const { return pid_; }
  [[nodiscard]] bool running();
  // Sends `sig` to the process group.
  void signal(int sig) const;
  // Waits up to `timeout` for the exit (pidfd + poll, no sleeping); returns
  // the exit status as from a shell (128 + signal), or -1 if it still runs.
  int wait(std::chrono::milliseconds timeout);
  // SIGTERM, then wait up to `grace`, then SIGKILL. Returns the status.
  int stop(std::chrono::milliseconds grace = std::chrono::seconds(5));
  [[nodiscard]] std::string output() const;  // the log so far

 private:
  int pid_;
  std::string log_;
  int status_ = -1;
  bool reaped_ = false;
};

class NetnsPair {
 public:
  // nullptr and the reason when this machine cannot make namespaces (not
  // root, no `ip`, no CAP_SYS_ADMIN) or open raw sockets in them.
  static std::unique_ptr<NetnsPair> create(std::string& why_not);
  ~NetnsPair();
  NetnsPair(const NetnsPair&) = delete;
  NetnsPair& operator=(const NetnsPair&) = delete;

  [[nodiscard]] const NetnsSide& a() const { return a_; }
  [[nodiscard]] const NetnsSide& b() const { return b_; }

  // `timeout 60 ip netns exec NS sh -c CMD`.
  NsRun run(const NetnsSide& side, const std::string& cmd) const;

  // `sh -c "exec CMD"` inside side's namespace, running on. nullptr (and
  // a failed test) if it cannot start.
  std::unique_ptr<NsProcess> start(const NetnsSide& side, const std::string& cmd) const;

  // Runs f on a new thread that has joined side's namespace; returns what f
  // returns (rethrows what it throws). Fails the test if setns fails.
  template <class F>
  auto in(const NetnsSide& side, F f) const -> decltype(f()) {
    std::packaged_task<decltype(f())()> task(std::move(f));
    auto result = task.get_future();
    // The task moves into the thread: if enter() fails it is destroyed
    // there unrun, and get() reports broken_promise instead of waiting.
    std::thread t([&side, task = std::move(task)]() mutable {
      if (enter(side)) task();
    });
    t.join();
    return result.get();  // broken_promise if enter() failed
  }
  // Like in(), but returns at once; join the thread when done.
  std::thread start_in(const NetnsSide& side, std::function<void()> f) const;

  // Joins the calling thread to side's namespace (for the threads above).
  static bool enter(const NetnsSide& side);

 private:
  NetnsPair() = default;
  NetnsSide a_, b_;
  bool made_a_ = false, made_b_ = false;
};

class NetnsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    pair_ = NetnsPair::create(why);
    if (!pair_) GTEST_SKIP() << "network namespaces unavailable, test skipped: " << why;
  }
  void TearDown() override { pair_.reset(); }
  [[nodiscard]] const NetnsSide& a() const { return pair_->a(); }
  [[nodiscard]] const NetnsSide& b() const { return pair_->b(); }
  [[nodiscard]] NetnsPair& pair() { return *pair_; }

 private:
  std::unique_ptr<NetnsPair> pair_;
};

}  // namespace plctest

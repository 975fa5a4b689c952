// A time bound for tests that drive a real-time debugger session.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "plc/debug/debugger.hpp"

namespace plctest {

// Bounds the debugger's real-time waits (`run until`): after a minute it
// interrupts them, so a condition that never comes fails the test instead
// of hanging it.
class Deadline {
 public:
  explicit Deadline(plc::debug::Debugger& d)
      : t_([this, &d] {
          std::unique_lock<std::mutex> l(m_);
          if (cv_.wait_for(l, std::chrono::minutes(1), [this] { return done_; })) return;
          while (!cv_.wait_for(l, std::chrono::milliseconds(100), [this] { return done_; }))
            d.interrupt();
        }) {}
  ~Deadline() {
    {
      std::lock_guard<std::mutex> l(m_);
      done_ = true;
    }
    cv_.notify_one();
    t_.join();
  }

 private:
  std::mutex m_;
  std::condition_variable cv_;
  bool done_ = false;
  std::thread t_;
};

}  // namespace plctest

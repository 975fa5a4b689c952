#include "test_programs.hpp"

#include <time.h>

#include <chrono>
#include <cstdint>
#include <stdexcept>

namespace plctest {

void Spinner::cycle(const ScanContext&) {
  ++scans;
  out = INT(1234);
  lamp = true;
  if (spin) {
    // CPU time, not wall time: a preempted spin on a loaded machine would
    // otherwise end with less CPU used than the test asked for.
    auto cpu_ns = [] {
      timespec ts{};
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
      return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
    };
    const std::int64_t until = cpu_ns() + std::int64_t(spin_us) * 1000;
    while (cpu_ns() < until) {
    }
  }
}

void Runaway::cycle(const ScanContext&) {
  ++scans;
  out = INT(1);
  const auto bound = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!release.load() && std::chrono::steady_clock::now() < bound) {
  }
  live_at_return.store(live.load());
  out = INT(2);
}

void Thrower::cycle(const ScanContext&) {
  out = true;
  if (fire) throw std::runtime_error("boom");
}

void RecordPoller::cycle(const ScanContext&) {
  const io::RecordStatus seen = req_.status();
  if (seen == io::RecordStatus::Done || seen == io::RecordStatus::Error) {
    ++answers;
    req_.reset();
  }
  if (req_.status() == io::RecordStatus::Idle) {
    req_.prepare_read(1);
    dev.submit(req_);
  }
  // Give a bus thread 100 us to answer while this scan runs.
  const io::RecordStatus mid = req_.status();
  const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(100);
  while (std::chrono::steady_clock::now() < until) {
  }
  if (req_.status() != mid) ++midscan_changes;
  answers_out = answers;
}

void PairWriter::cycle(const ScanContext&) {
  ++first;
  const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(work_us);
  while (std::chrono::steady_clock::now() < until) {
  }
  second = first;
}

PLC_REGISTER_PROGRAM(ReleaseLog)
PLC_REGISTER_PROGRAM(PairWriter)
PLC_REGISTER_PROGRAM(RecordPoller)
PLC_REGISTER_PROGRAM(Spinner)
PLC_REGISTER_PROGRAM(Runaway)
PLC_REGISTER_PROGRAM(BitWriter)
PLC_REGISTER_PROGRAM(LoopCounter)
PLC_REGISTER_PROGRAM(Thrower)
PLC_REGISTER_PROGRAM(Shapes)
PLC_REGISTER_PROGRAM(Guarded)

}  // namespace plctest

#include "plc/task_stats.hpp"

#include <utility>

namespace plc {

void LiveTaskStats::record_scan(std::int64_t scan_ns) {
  seq_.write_begin();
  scan_ns_.record(scan_ns);
  ++scans_;
  seq_.write_end();
  help_reader_if_asked();
}

void LiveTaskStats::record_latency(std::int64_t latency_ns) {
  seq_.write_begin();
  latency_ns_.record(latency_ns);
  seq_.write_end();
  help_reader_if_asked();
}

void LiveTaskStats::record_overrun(std::uint64_t skipped) {
  seq_.write_begin();
  ++overruns_;
  skipped_ += skipped;
  seq_.write_end();
  help_reader_if_asked();
}

void LiveTaskStats::record_paused_release() {
  seq_.write_begin();
  ++paused_releases_;
  seq_.write_end();
  help_reader_if_asked();
}

void LiveTaskStats::set_stopped(bool watchdog, std::string reason) {
  if (stop_published_.load(std::memory_order_relaxed)) return;
  watchdog_tripped_ = watchdog;
  faulted_ = !watchdog;
  stop_reason_ = std::move(reason);
  stop_published_.store(true, std::memory_order_release);
}

void LiveTaskStats::copy_counters(TaskStats& s) const {
  s.scan_ns = Histogram(scan_ns_);
  s.latency_ns = Histogram(latency_ns_);
  s.scans = scans_;
  s.overruns = overruns_;
  s.skipped = skipped_;
  s.paused_releases = paused_releases_;
}

void LiveTaskStats::help_reader() {
  int asked = kAsked;
  if (!help_.compare_exchange_strong(asked, kCopying, std::memory_order_acquire)) return;
  copy_counters(helped_);  // between two updates: this thread's own, consistent
  help_.store(kCopied, std::memory_order_release);
}

TaskStats LiveTaskStats::snapshot() const {
  TaskStats s;
  auto copy = [&] { copy_counters(s); };
  if (!seq_.read(copy, 64)) {
    std::lock_guard<std::mutex> lock(readers_);
    help_.store(kAsked, std::memory_order_release);
    // Bounded: a writer that keeps writing answers at its next update; one
    // that went quiet leaves the lock-free copy free to succeed.
    for (int i = 0; i < 1'000'000; ++i) {
      if (help_.load(std::memory_order_acquire) == kCopied) {
        s = helped_;  // its stop fields are never set (below)
        break;
      }
      if (i % 64 == 63) {
        int asked = kAsked;
        if (help_.compare_exchange_strong(asked, kIdle, std::memory_order_relaxed)) {
          if (seq_.read(copy, 64)) break;  // withdrawn, and the writer is quiet
          help_.store(kAsked, std::memory_order_release);
        }
      }
      std::this_thread::yield();
    }
    help_.store(kIdle, std::memory_order_relaxed);
  }
  if (stop_published_.load(std::memory_order_acquire)) {
    s.watchdog_tripped = watchdog_tripped_;
    s.faulted = faulted_;
    s.stop_reason = stop_reason_;
  }
  return s;
}

}  // namespace plc

#include "plc/task_stats.hpp"

#include <utility>

namespace plc {

void LiveTaskStats::record_scan(std::int64_t scan_ns) {
  seq_.write_begin();
  scan_ns_.record(scan_ns);
  ++scans_;
  seq_.write_end();
}

void LiveTaskStats::record_latency(std::int64_t latency_ns) {
  seq_.write_begin();
  latency_ns_.record(latency_ns);
  seq_.write_end();
}

void LiveTaskStats::record_overrun(std::uint64_t skipped) {
  seq_.write_begin();
  ++overruns_;
  skipped_ += skipped;
  seq_.write_end();
}

void LiveTaskStats::record_paused_release() {
  seq_.write_begin();
  ++paused_releases_;
  seq_.write_end();
}

void LiveTaskStats::set_stopped(bool watchdog, std::string reason) {
  if (stop_published_.load(std::memory_order_relaxed)) return;
  watchdog_tripped_ = watchdog;
  faulted_ = !watchdog;
  stop_reason_ = std::move(reason);
  stop_published_.store(true, std::memory_order_release);
}

TaskStats LiveTaskStats::snapshot() const {
  TaskStats s;
  seq_.read([&] {
    s.scan_ns = Histogram(scan_ns_);
    s.latency_ns = Histogram(latency_ns_);
    s.scans = scans_;
    s.overruns = overruns_;
    s.skipped = skipped_;
    s.paused_releases = paused_releases_;
  });
  if (stop_published_.load(std::memory_order_acquire)) {
    s.watchdog_tripped = watchdog_tripped_;
    s.faulted = faulted_;
    s.stop_reason = stop_reason_;
  }
  return s;
}

}  // namespace plc

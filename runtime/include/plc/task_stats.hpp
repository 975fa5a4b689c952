// Per-task timing statistics: scan (execution) time and wake latency as
// histograms, plus overruns and skipped releases.
//
// TaskStats is a plain snapshot. LiveTaskStats is where a task's scan thread
// keeps them while it runs: only that thread records (no lock, no
// allocation, no waiting: a sequence lock, seqlock.hpp), and any thread
// (the console's `stats` and `step`, plcrun's status line, the HMI) takes a
// consistent snapshot at any time: every figure in it from the same scans.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>

#include "plc/histogram.hpp"
#include "plc/seqlock.hpp"

namespace plc {

struct TaskStats {
  Histogram scan_ns;     // time from scan start to scan end (latch..publish)
  Histogram latency_ns;  // real time only: wake-up time minus release time
  std::uint64_t scans = 0;
  std::uint64_t overruns = 0;         // scans that ended after their next release
  std::uint64_t skipped = 0;          // releases dropped because of overruns
  std::uint64_t paused_releases = 0;  // real time: releases not scanned while paused
  bool watchdog_tripped = false;
  bool faulted = false;     // stopped by an exception from a program
  std::string stop_reason;  // why the task stopped early ("" = it did not)
};

class LiveTaskStats {
 public:
  // The task's scan thread only.
  void record_scan(std::int64_t scan_ns);
  // A scan that was not timed (virtual time times a sample). Inline: it is
  // most scans of a cell in virtual time, and a call costs as much as it.
  // No write bracket: it changes one cell alone (one release store), so a
  // reader's copy sees every cell either before it or after it, and both
  // are whole states (test: TaskStats.UntimedCountsNeedNoBracket).
  void count_scan() {
    ++scans_;
    help_reader_if_asked();
  }
  void record_latency(std::int64_t latency_ns);
  void record_overrun(std::uint64_t skipped);
  void record_paused_release();

  // Once, by the thread that stops the task (its scan thread, or the
  // watchdog's in real time); readers see the reason only when it is
  // complete.
  void set_stopped(bool watchdog, std::string reason);

  // Any thread. scans() is an acquire: whoever sees n scans sees everything
  // the task's first n scans wrote (the debugger's `step` waits on it).
  [[nodiscard]] std::uint64_t scans() const { return scans_; }
  [[nodiscard]] bool watchdog_tripped() const {
    return stop_published_.load(std::memory_order_acquire) && watchdog_tripped_;
  }
  // "" until the stop is published, then why the task stopped (it never
  // changes again).
  [[nodiscard]] std::string_view stop_reason() const {
    return stop_published_.load(std::memory_order_acquire) ? std::string_view(stop_reason_)
                                                           : std::string_view();
  }
  [[nodiscard]] TaskStats snapshot() const;

 private:
  // The fallback of snapshot() when the writer records so often that a
  // copy keeps overlapping its writes (a tight virtual-time loop, a slow
  // sanitizer build): the reader asks (help_ 0 -> 1), the writer claims the
  // request (1 -> 2) at the end of its next update, copies its figures into
  // helped_ and hands them over (2 -> 3); the reader takes them (3 -> 0).
  // The writer never waits: it pays one copy per request.
  void help_reader_if_asked() {
    if (help_.load(std::memory_order_relaxed) == kAsked) help_reader();
  }
  void help_reader();
  void copy_counters(TaskStats& s) const;  // everything but the stop fields
  static constexpr int kIdle = 0, kAsked = 1, kCopying = 2, kCopied = 3;

  SeqLock seq_;
  BasicHistogram<SeqLockCell> scan_ns_, latency_ns_;
  SeqLockCell<std::uint64_t> scans_, overruns_, skipped_, paused_releases_;
  std::atomic<bool> stop_published_{false};
  bool watchdog_tripped_ = false, faulted_ = false;
  std::string stop_reason_;
  mutable std::mutex readers_;  // one reader at a time asks the writer
  mutable std::atomic<int> help_{kIdle};
  mutable TaskStats helped_;  // written by the writer between kCopying and kCopied
};

}  // namespace plc

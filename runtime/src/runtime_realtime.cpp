// Real-time execution: one SCHED_FIFO thread per task on absolute
// CLOCK_MONOTONIC deadlines, a watchdog thread, and the overrun policy.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "plc/realtime_thread.hpp"
#include "plc/release_schedule.hpp"
#include "plc/runtime.hpp"
#include "plc/thread_guard.hpp"
#include "task_thread.hpp"

namespace plc {
namespace {

// IEC priority 0 (highest) .. 48 maps to SCHED_FIFO 49 .. 1: below the
// default priority (50) of PREEMPT_RT's interrupt threads, so a busy PLC task
// cannot starve the network interrupts its own fieldbus needs.
int fifo_priority(int iec_priority) { return std::clamp(49 - iec_priority, 1, 49); }

}  // namespace

void Runtime::run_realtime(TIME span) {
  // Memory locked and timer slack at 1 ns: page faults and the kernel's
  // default 50 us slack would otherwise show up directly as wake-up jitter.
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
    std::fprintf(stderr, "plcrun: warning: mlockall failed (%s): page faults may add latency\n",
                 std::strerror(errno));
  prctl(PR_SET_TIMERSLACK, 1UL, 0, 0, 0);
  // Keep the CPUs out of deep idle states while we run (as cyclictest does):
  // waking from them costs tens of microseconds. The request holds while the
  // file stays open.
  const int dma_fd = ::open("/dev/cpu_dma_latency", O_RDWR | O_CLOEXEC);
  if (dma_fd >= 0) {
    const std::int32_t zero = 0;
    if (::write(dma_fd, &zero, sizeof zero) != sizeof zero) {
      std::fprintf(stderr,
                   "plcrun: warning: /dev/cpu_dma_latency not set: idle states may add latency\n");
    }
  }

  rt_running_.store(true);
  const std::int64_t t0 = mono_ns() + 5'000'000;  // common phase for all tasks
  const std::int64_t end = t0 + span.count();
  std::vector<std::thread> threads;
  std::vector<std::shared_ptr<TaskThread>> records;
  for (auto& t : tasks_) {
    // The thread holds its record for its whole life (TaskThread).
    auto rec = records.emplace_back(std::make_shared<TaskThread>());
    rec->owner = t.get();
    threads.emplace_back([this, task = t.get(), t0, rec] {
      TaskThread::current() = rec.get();
      // scan() stops the task on what a scan throws; this catches the rest
      // of the loop: the task stops, its outputs safe, the others run on.
      run_guarded(
          "task '" + task->name + "'", [&] { realtime_task_loop(*task, t0); },
          [&](std::string_view what) {
            trip(*task, "task thread failed: " + std::string(what), false);
            task->busy.store(false, std::memory_order_release);
          });
    });
  }
  start_watchdog();

  while (!stop_requested() && mono_ns() < end) {
    const std::int64_t next = std::min(end, mono_ns() + 10'000'000);
    sleep_until_ns(next);
    bool any = false;
    for (const auto& t : tasks_) any |= !t->stopped.load();
    if (!any) break;
  }
  rt_running_.store(false);
  for (std::size_t i = 0; i < threads.size(); ++i) {
    // A task the watchdog stopped may stay in its program forever: leave
    // its thread there rather than hang. From then on the thread touches
    // nothing of ours when the program returns (TaskThread). A thread in
    // runtime code always comes back: it is joined.
    int in_program = TaskThread::InProgram;
    if (tasks_[i]->stats.watchdog_tripped() &&
        records[i]->state.compare_exchange_strong(in_program, TaskThread::LeftBehind)) {
      threads[i].detach();
      left_behind_.push_back(records[i]);
    } else {
      threads[i].join();
    }
  }
  stop_watchdog();
  if (dma_fd >= 0) ::close(dma_fd);
  now_ = TIME(std::max<std::int64_t>(0, std::min(mono_ns(), end) - t0));
}

void Runtime::realtime_task_loop(TaskRuntime& t, std::int64_t t0) {
  if (const int rc = set_fifo_priority(fifo_priority(t.priority)); rc != 0) {
    static std::atomic<bool> warned{false};  // once, not once per task
    if (!warned.exchange(true))
      warn_fifo_refused("plcrun", rc,
                        "tasks run at normal priority and wake-up latency will be higher (run as "
                        "root or grant CAP_SYS_NICE)");
  }
  const std::int64_t period = t.period.count();
  std::int64_t k = 0;
  while (rt_running_.load(std::memory_order_relaxed) &&
         !t.stopped.load(std::memory_order_relaxed)) {
    const std::int64_t release = t0 + k * period;
    sleep_until_ns(release);
    if (!rt_running_.load(std::memory_order_relaxed) || t.stopped.load(std::memory_order_relaxed))
      break;
    const std::int64_t wake = mono_ns();
    // Busy before looking at the pause and stop flags (all sequentially
    // consistent): either we see them, or wait_until_idle (or the debugger's
    // check that the task is quiet) sees us busy.
    t.busy.store(true);
    if (t.stopped.load()) {
      t.busy.store(false, std::memory_order_release);
      break;
    }
    // Paused (debugger): skip the scan entirely; the plugins keep
    // exchanging the last outputs. A step budget lets single scans through.
    if (paused_.load() && t.step_budget.load(std::memory_order_acquire) <= 0) {
      t.stats.record_paused_release();
      t.busy.store(false, std::memory_order_release);
      k = next_release(k, t0, period, mono_ns()).index;
      continue;
    }
    if (paused()) t.step_budget.fetch_sub(1, std::memory_order_acq_rel);
    t.stats.record_latency(wake - release);
    if (!scan(t, TIME(k * period))) return;  // left behind: touch nothing
    const NextRelease n = next_release(k, t0, period, mono_ns());
    if (n.overrun) t.stats.record_overrun(n.skipped);
    t.busy.store(false, std::memory_order_release);
    k = n.index;
  }
}

void Runtime::hand_over_left_behind() {
  for (const std::shared_ptr<TaskThread>& rec : left_behind_) {
    int left = TaskThread::LeftBehind;
    // Exited: the program came back and the thread has ended; nothing to do.
    if (!rec->state.compare_exchange_strong(left, TaskThread::Abandoned)) continue;
    // Still inside the program: the record keeps the task (its private
    // image, where the program's located variables live) and the task's
    // programs; they go when the thread ends (never, if the program never
    // returns: a deliberate leak, the price of not killing a thread).
    for (auto& t : tasks_)
      if (t.get() == rec->owner) rec->task = std::move(t);
    if (!rec->task) continue;
    const std::vector<Program*>& mine = rec->task->programs;
    for (auto& [name, p] : programs_)
      if (std::find(mine.begin(), mine.end(), p.get()) != mine.end())
        rec->programs.push_back(std::move(p));
  }
  left_behind_.clear();
}

bool Runtime::wait_until_idle(std::chrono::nanoseconds timeout) const {
  if (!lock_image_) return true;  // virtual time: nothing runs concurrently
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    bool idle = true;
    for (const auto& t : tasks_) idle &= !t->busy.load();  // pairs with the store above
    if (idle) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}

void Runtime::start_watchdog() {
  bool any = false;
  for (const auto& t : tasks_) any |= t->watchdog > 0;
  if (!any || watchdog_running_.exchange(true)) return;
  // Without its watchdog the cell may not run on: it stops cleanly (every
  // output safe, Runtime::finish) at the next boundary.
  watchdog_thread_ = std::thread([this] {
    run_guarded(
        "watchdog", [this] { watchdog_loop(); },
        [this](std::string_view) {
          failure_ = "the watchdog thread failed";
          request_stop();
        });
  });
}

void Runtime::stop_watchdog() {
  if (watchdog_running_.exchange(false) && watchdog_thread_.joinable()) watchdog_thread_.join();
}

void Runtime::watchdog_loop() {
  const bool virtual_time = mode_ == io::ClockMode::Virtual;
  std::int64_t fastest = INT64_MAX;
  for (const auto& t : tasks_) fastest = std::min<std::int64_t>(fastest, t->period.count());
  const std::int64_t poll =
      std::clamp<std::int64_t>(fastest / 4, virtual_time ? 1'000'000 : 100'000, 10'000'000);
  if (!virtual_time) {
    // Above every task (max task priority is 49); where refused, the tasks'
    // own warning has said so.
    (void)set_fifo_priority(50);
  }
  // Virtual time: per task, the scan we are watching and the scan thread's
  // CPU time when we first saw it running.
  struct Seen {
    std::uint64_t seq = 0;
    std::int64_t cpu0 = 0;
  };
  std::vector<Seen> seen(tasks_.size());
  auto cpu_now = [this] {
    timespec ts{};
    clock_gettime(scan_thread_cpu_clock_, &ts);
    return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
  };
  while (watchdog_running_.load(std::memory_order_relaxed)) {
    const std::int64_t now = mono_ns();
    for (std::size_t i = 0; i < tasks_.size(); ++i) {
      TaskRuntime& t = *tasks_[i];
      if (t.watchdog <= 0 || t.stopped.load() || t.trip_requested.load()) continue;
      const std::int64_t limit = std::int64_t(t.watchdog * double(t.period.count()));
      const std::int64_t started = t.scan_started_ns.load(std::memory_order_acquire);
      if (started < 0) continue;
      if (virtual_time) {
        const std::int64_t cpu_limit = std::max(limit, kVirtualWatchdogFloorNs);
        const std::uint64_t seq = t.scan_seq.load(std::memory_order_relaxed);
        if (seq != seen[i].seq) {
          seen[i] = {seq, cpu_now()};
          continue;
        }
        const std::int64_t used = cpu_now() - seen[i].cpu0;
        if (used > cpu_limit) {
          t.trip_reason = "watchdog: scan used more than " + std::to_string(used / 1000) +
                          " us of CPU, limit " + std::to_string(cpu_limit / 1000) +
                          " us (virtual time: a runaway scan, at least 0.5 s of CPU)";
          t.trip_requested.store(true, std::memory_order_release);
          std::fprintf(stderr,
                       "plcrun: task '%s' exceeded its watchdog; it stops when the scan returns\n",
                       t.name.c_str());
        }
      } else if (now - started > limit) {
        trip(t,
             "watchdog: scan running for " + std::to_string((now - started) / 1000) +
                 " us, limit " + std::to_string(limit / 1000) + " us",
             true);
      }
    }
    sleep_until_ns(now + poll);
  }
}

}  // namespace plc

// One scan of a task, and what happens when a task must stop: watchdog,
// exceptions, and the final safe state.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>

#include "plc/detail/small_copy.hpp"
#include "plc/io/current_owner.hpp"
#include "plc/online_change.hpp"
#include "plc/runtime.hpp"
#include "plc/thread_guard.hpp"
#include "task_thread.hpp"

namespace plc {
namespace {

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

[[gnu::always_inline]] inline void copy_spans(const std::vector<ImageSpan>& spans) {
  for (const ImageSpan& s : spans) detail::copy_bytes(s.dst, s.src, s.n);
}

template <class M>
struct MaybeLock {
  MaybeLock(M& m, bool on) : m_(m), on_(on) {
    if (on_) m_.lock();
  }
  ~MaybeLock() {
    if (on_) m_.unlock();
  }
  M& m_;
  bool on_;
};

}  // namespace

// A scan in two halves: both take the image lock once. scan() runs them
// back to back; a replay runs them apart (Runtime::latch_scan/finish_scan) to
// reproduce how the locked sections of several real-time tasks interleaved.
//
// What a program throws stops its task (scan_finish). What the rest of the
// scan throws - a hook, an observer, a plugin's latch or publish - stops the
// task the same way, in real and in virtual time: the scan is over, its
// outputs go to their safe values, the other tasks run on.
//
// scan() only chooses, so that the virtual-time loop inlines it: each of
// the two catches what its scan throws.
bool Runtime::scan(TaskRuntime& t, TIME now) {
  if (plain_scans_) return scan_plain(t, now);
  return scan_hooked(t, now);
}

bool Runtime::scan_hooked(TaskRuntime& t, TIME now) {
  try {
    // The latch has made t the current owner; nothing ran since.
    return run_programs_and_publish(t, scan_latch(t, now));
  } catch (const std::exception& e) {
    scan_failed(t, e.what());
  } catch (...) {
    scan_failed(t, "an exception that is not a std::exception");
  }
  return true;
}

void Runtime::scan_failed(TaskRuntime& t, std::string_view what) {
  io::detail::set_current_owner(-1);
  t.scan_started_ns.store(-1, std::memory_order_release);
  report_thread_failure("task '" + t.name + "'", what);
  trip(t, "scan failed: " + std::string(what), false);
}

// Virtual time times one scan in kVirtualTimedEvery, the first of each
// kVirtualTimedEvery: timing_phase counts down the untimed ones between (a
// test and a decrement; the count up and a modulo cost more per scan).
[[gnu::always_inline]] inline bool Runtime::timed_now(TaskRuntime& t) {
  if (t.timing_phase == 0) [[unlikely]] {
    t.timing_phase = kVirtualTimedEvery - 1;
    return true;
  }
  --t.timing_phase;
  return false;
}

// Both inline in their scans (a frame each per scan otherwise).
[[gnu::always_inline]] inline void Runtime::latch_devices(TaskRuntime& t, TIME now) {
  latch_device_bytes(t);
  latch_states(t, now);
}

[[gnu::always_inline]] inline void Runtime::latch_device_bytes(TaskRuntime& t) {
  if (plugins_enabled_) {
    for (const TaskRuntime::DirectDevice& c : t.direct)
      detail::copy_bytes(c.image_in, c.device_in, c.in_bytes);
    if (t.any_via_plugin) [[unlikely]]
      for (const TaskRuntime::PluginDevice& d : t.via_plugin)
        if (d.in_bytes) d.plugin->latch_inputs(d.index, {d.image_in, d.in_bytes});
  }
}

[[gnu::always_inline]] inline void Runtime::latch_states(TaskRuntime& t, TIME now) {
  // 1a: the answers to this task's acyclic requests and its devices'
  // states become visible now, so they never change during the scan.
  // Answers only while a link tracks a request (most scans: none does).
  // The states only when a link's state changed since this task's last
  // latch of them (most scans: none did): otherwise each link's latched
  // state equals its present one (a latch, set_deferred() and force_state()
  // leave them equal; only set_state() makes them differ, and counts it) and
  // latch_state() would do nothing. The total read before the states: a
  // change counted after this read makes the next latch look. Test:
  // ScanSemantics.LatchSkipsStatesOnlyWhenNoneChanged. The states in a
  // pointer loop with its bounds and the scan number read once: the acquire
  // in latch_state() would otherwise make the compiler reload them for every
  // device, every scan.
  if (links_tracking_.load(std::memory_order_acquire) != 0) deliver_answers(t);
  const std::uint64_t changes = state_changes_.load(std::memory_order_acquire);
  if (changes == t.latched_changes) return;
  t.latched_changes = changes;
  const std::uint64_t scan_no = t.cycle + 1;
  for (DeviceRuntime* d : t.devices) d->link->latch_state(scan_no, now);
}

void Runtime::deliver_answers(TaskRuntime& t) {
  DeviceRuntime* const first = devices_.data();
  DeviceRuntime* const last = first + devices_.size();
  for (DeviceRuntime* d = first; d != last; ++d) {
    io::DeviceLink& link = *d->link;
    if (!link.tracking()) continue;
    const auto i = static_cast<std::size_t>(d - first);
    link.deliver_answered(static_cast<int>(t.order), [&](const io::RecordRequest& r) {
      for (ScanHooks* h : hooks_) h->on_answer(t, i, r);
    });
  }
}

[[gnu::always_inline]] inline void Runtime::publish_devices(TaskRuntime& t) {
  if (!plugins_enabled_) return;
  for (const TaskRuntime::DirectDevice& c : t.direct)
    detail::copy_bytes(c.device_out, c.image_out, c.out_bytes);
  if (t.any_via_plugin) [[unlikely]]
    for (const TaskRuntime::PluginDevice& d : t.via_plugin)
      if (d.out_bytes) d.plugin->publish_outputs(d.index, {d.image_out, d.out_bytes});
}

// scan_latch() and run_programs_and_publish() as they run with no hook set
// in virtual time (no lock, no whole-image scan, no merge of bits: both
// halves in one call), step for step; what differs is only what they would
// do for hooks or another thread. Test: PlainScanEqualsHookedScan.
// The scan in two copies, timed and untimed (one in kVirtualTimedEvery is
// timed, as in scan_latch()): the untimed one, nearly every scan, then keeps
// no start time and no flag across the programs to choose record_scan() or
// count_scan() by (the test compares the timed counts with the hooked scan's).
//
// The body inline in the virtual-time loop (run_virtual(), nearly every
// scan of a virtual-time run: a call, a frame and six saved registers per
// scan otherwise) and in scan_plain(), which the other callers (tick(),
// step_scan()) reach through scan().
bool Runtime::scan_plain(TaskRuntime& t, TIME now) { return scan_plain_inline(t, now); }

[[gnu::always_inline]] inline bool Runtime::scan_plain_inline(TaskRuntime& t, TIME now) try {
  if (ProgramSwap* s = t.swap.load(std::memory_order_acquire)) apply_program_swap(t, *s);
  const auto scan = [&]<bool timed>() __attribute__((always_inline)) {
    const std::int64_t start = timed ? steady_ns() : 0;
    t.scan_seq.store(t.scan_seq.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
    t.scan_started_ns.store(start, std::memory_order_release);
    t.scan_timed = timed;
    t.scan_time = now;
    t.whole_image_scan = false;
    t.merge_bits = false;
    // Every device direct (the usual virtual-time run): its inputs and
    // copy_in in one loop (plain_in), before the states' latch, which
    // copies no bytes, and the owner, which no copy reads.
    const bool fused = t.plain_fused;
    if (fused) [[likely]] {
      copy_spans(t.plain_in);
      latch_states(t, now);
      io::detail::set_current_owner(static_cast<int>(t.order));
    } else {
      latch_devices(t, now);
      io::detail::set_current_owner(static_cast<int>(t.order));
      copy_spans(t.copy_in);
    }
    const ScanContext ctx{now, t.period, t.cycle};
    try {
      for (Program* p : t.programs) p->cycle(ctx);
    } catch (const std::exception& e) {
      trip(t, std::string("program threw: ") + e.what(), false);
    } catch (...) {
      trip(t, "program threw a non-standard exception", false);
    }
    if (t.trip_requested.load(std::memory_order_acquire)) trip(t, t.trip_reason, true);
    if (!t.stopped.load(std::memory_order_acquire)) {
      if (fused) [[likely]] {
        copy_spans(t.plain_out);  // copy_out, then the devices' outputs
      } else {
        copy_spans(t.copy_out);
        publish_devices(t);
      }
    }
    io::detail::set_current_owner(-1);
    if constexpr (timed)
      t.stats.record_scan(steady_ns() - start);
    else
      t.stats.count_scan();
    t.scan_started_ns.store(-1, std::memory_order_release);
    if (any_observer_) [[unlikely]]
      for (const auto& o : observers_) o(t, ctx);
    ++t.cycle;
  };
  if (timed_now(t)) [[unlikely]]
    scan.template operator()<true>();
  else
    scan.template operator()<false>();
  return true;
} catch (const std::exception& e) {
  scan_failed(t, e.what());
  return true;
} catch (...) {
  scan_failed(t, "an exception that is not a std::exception");
  return true;
}

ScanContext Runtime::scan_latch(TaskRuntime& t, TIME now) {
  // 0: an online change for this task switches here, between two scans.
  if (ProgramSwap* s = t.swap.load(std::memory_order_acquire)) apply_program_swap(t, *s);
  // The scan's duration for the statistics: every scan in real time; in
  // virtual time one in kVirtualTimedEvery, since two clock reads cost as
  // much as a small cell's whole scan there (the sample still shows what a
  // scan costs; every scan is counted).
  const bool timed = lock_image_ || timed_now(t);
  const std::int64_t start = timed ? steady_ns() : 0;
  // The watchdog's bookkeeping (the recorder's arm() also looks at
  // scan_started_ns). One writer: a load and a store, no locked instruction.
  t.scan_seq.store(t.scan_seq.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  t.scan_started_ns.store(start, std::memory_order_release);
  t.scan_timed = timed;
  t.scan_time = now;
  t.whole_image_scan = whole_image_hooks_ != 0;
  {
    // 1: latch this task's devices into the global %I, take a private copy.
    MaybeLock lock(image_mutex_, lock_image_);
    latch_devices(t, now);
    io::detail::set_current_owner(static_cast<int>(t.order));
    for (ScanHooks* h : hooks_) h->after_latch(t, global_);
    if (t.whole_image_scan)
      t.image.copy_from(global_);
    else
      copy_spans(t.copy_in);
  }
  // Real time merges the bits the scan changed (another task may have
  // written the global image meanwhile), so it keeps the %Q/%M as they were
  // at the latch; in virtual time nothing runs between a latch and its merge.
  if (t.whole_image_scan) {
    auto q = t.image.area(io::Area::Output);
    auto m = t.image.area(io::Area::Memory);
    std::copy(q.begin(), q.end(), t.before.area(io::Area::Output).begin());
    std::copy(m.begin(), m.end(), t.before.area(io::Area::Memory).begin());
  } else if (lock_image_) {
    copy_spans(t.keep);
  }
  t.merge_bits = lock_image_;
  return ScanContext{now, t.period, t.cycle};
}

bool Runtime::scan_finish(TaskRuntime& t, const ScanContext& ctx) {
  // A replay may have latched another task in between (same thread).
  io::detail::set_current_owner(static_cast<int>(t.order));
  return run_programs_and_publish(t, ctx);
}

bool Runtime::run_programs_and_publish(TaskRuntime& t, const ScanContext& ctx) {
  // 3: the programs. A program that the watchdog stopped may come back
  // after the run left its thread behind (or the runtime is gone): then
  // nothing here may be touched any more (TaskThread). Only a real-time
  // task thread can be left behind.
  for (ScanHooks* h : hooks_) h->before_programs(t, ctx);
  const bool task_thread = lock_image_;
  try {
    for (std::size_t i = 0; i < t.programs.size(); ++i) {
      for (ScanHooks* h : hooks_) h->before_program(t, i, ctx);
      if (task_thread) TaskThread::enter_program();
      t.programs[i]->cycle(ctx);
      if (task_thread && !TaskThread::leave_program()) return false;
    }
  } catch (const std::exception& e) {
    if (task_thread && !TaskThread::leave_program()) return false;
    trip(t, std::string("program threw: ") + e.what(), false);
  } catch (...) {
    if (task_thread && !TaskThread::leave_program()) return false;
    trip(t, "program threw a non-standard exception", false);
  }
  if (t.trip_requested.load(std::memory_order_acquire)) trip(t, t.trip_reason, true);
  for (ScanHooks* h : hooks_) h->after_programs(t, ctx);

  {
    // 5: merge what this scan changed, publish this task's devices.
    MaybeLock lock(image_mutex_, lock_image_);
    if (!t.stopped.load(std::memory_order_acquire)) {
      if (t.whole_image_scan) {
        for (io::Area a : {io::Area::Output, io::Area::Memory})
          io::merge_changes(global_.area(a), t.before.area(a), t.image.area(a));
      } else if (t.merge_bits) {
        for (const ImageSpan& s : t.merge_out)
          io::merge_changes({s.dst, s.n}, {s.before, s.n}, {s.src, s.n});
      } else {
        // Virtual time, both halves in one scan(): the global bytes are
        // still those the latch copied.
        copy_spans(t.copy_out);
      }
      for (ScanHooks* h : hooks_) h->before_publish(t, global_);
      publish_devices(t);
    }
  }
  io::detail::set_current_owner(-1);
  if (t.scan_timed)
    t.stats.record_scan(steady_ns() - t.scan_started_ns.load(std::memory_order_relaxed));
  else
    t.stats.count_scan();
  t.scan_started_ns.store(-1, std::memory_order_release);
  if (any_observer_) [[unlikely]]
    for (const auto& o : observers_) o(t, ctx);
  ++t.cycle;
  return true;
}

void Runtime::trip(TaskRuntime& t, const std::string& reason, bool watchdog) {
  if (t.stopped.exchange(true)) return;
  tasks_alive_.fetch_sub(1, std::memory_order_relaxed);
  t.stats.set_stopped(watchdog, reason);
  {
    MaybeLock lock(image_mutex_, lock_image_);
    apply_safe_outputs(&t.owned_q);
    publish_all();
    for (ScanHooks* h : hooks_) h->on_stop(t, global_);
  }
  std::fprintf(stderr,
               "plcrun: task '%s' stopped at %.6f s: %s; its outputs are at their safe values\n",
               t.name.c_str(), std::chrono::duration<double>(now_).count(), reason.c_str());
}

void Runtime::apply_safe_outputs(const std::vector<std::uint8_t>* mask) {
  auto q = global_.area(io::Area::Output);
  for (std::size_t i = 0; i < q.size(); ++i) {
    const std::uint8_t mk = mask ? (*mask)[i] : 0xFF;
    q[i] = static_cast<std::uint8_t>((q[i] & ~mk) | (safe_q_[i] & mk));
  }
}

void Runtime::publish_all() {
  if (!plugins_enabled_) return;
  auto gq = global_.area(io::Area::Output);
  for (auto& d : devices_)
    if (d.sizes.output_bytes)
      d.plugin->publish_outputs(d.index, gq.subspan(d.out.byte, d.sizes.output_bytes));
}

void Runtime::start(io::ClockMode mode) {
  if (started_) return;
  if (mode == io::ClockMode::Virtual && virtual_clock_error_) throw *virtual_clock_error_;
  mode_ = mode;
  lock_image_ = mode == io::ClockMode::RealTime;
  plain_scans_ = !lock_image_ && hooks_.empty();
  for (auto& [name, p] : plugins_) {
    if (!plugins_enabled_) break;
    try {
      p->start(mode);
    } catch (const std::exception& e) {
      throw io::PluginStartError("plugin '" + name + "' failed to start: " + e.what());
    }
  }
  // The devices whose plugin lets the scan copy their bytes itself (both
  // directions, each the size add_device() gave: the runtime's sizes).
  for (DeviceRuntime& d : devices_) {
    d.direct_in = nullptr;
    d.direct_out = nullptr;
    if (!plugins_enabled_) continue;
    const auto io = d.plugin->direct_io(d.index);
    if (!io || io->in.size() != d.sizes.input_bytes || io->out.size() != d.sizes.output_bytes)
      continue;
    d.direct_in = io->in.data();
    d.direct_out = io->out.data();
  }
  plan_device_io();
  // Devices see the safe outputs until the first scan publishes.
  publish_all();
  started_ = true;
  if (mode == io::ClockMode::Virtual) {
    pthread_getcpuclockid(pthread_self(), &scan_thread_cpu_clock_);
    start_watchdog();
  }
  first_tick_ = true;
}

// Each task's devices split into the ones the scan copies itself and the
// ones their plugin exchanges (TaskRuntime::direct, via_plugin).
void Runtime::plan_device_io() {
  auto gi = global_.area(io::Area::Input);
  auto gq = global_.area(io::Area::Output);
  for (auto& t : tasks_) {
    t->direct.clear();
    t->via_plugin.clear();
    for (DeviceRuntime* d : t->devices) {
      // A device of no bytes one way exchanges nothing that way (its image
      // offset may then be anything: no pointer is formed from it).
      const std::size_t ni = d->sizes.input_bytes, no = d->sizes.output_bytes;
      if (!d->direct_in) {
        t->via_plugin.push_back({d->plugin, d->index, ni ? gi.data() + d->in.byte : nullptr, ni,
                                 no ? gq.data() + d->out.byte : nullptr, no});
        continue;
      }
      t->direct.push_back({ni ? gi.data() + d->in.byte : nullptr, d->direct_in, ni, d->direct_out,
                           no ? gq.data() + d->out.byte : nullptr, no});
    }
    t->any_via_plugin = !t->via_plugin.empty();
    t->plain_fused = plugins_enabled_ && !t->any_via_plugin;
    // The plain scan's copies when every device is direct (scan_plain()):
    // the devices' inputs, then copy_in (which reads them); copy_out, then
    // the devices' outputs (which read it). copy_in and copy_out are made
    // at build, after the build's call of this, which calls it again.
    t->plain_in.clear();
    t->plain_out.clear();
    for (const TaskRuntime::DirectDevice& c : t->direct)
      if (c.in_bytes) t->plain_in.push_back({c.image_in, c.device_in, nullptr, c.in_bytes});
    t->plain_in.insert(t->plain_in.end(), t->copy_in.begin(), t->copy_in.end());
    t->plain_out = t->copy_out;
    for (const TaskRuntime::DirectDevice& c : t->direct)
      if (c.out_bytes) t->plain_out.push_back({c.device_out, c.image_out, nullptr, c.out_bytes});
  }
}

void Runtime::remove_hooks(ScanHooks* h) {
  if (std::erase(hooks_, h) && h->whole_image()) --whole_image_hooks_;
  plain_scans_ = !lock_image_ && hooks_.empty();
}

// Virtual time: step() is the plugin's thread. What it throws fails the
// plugin as a failed thread would (its devices to Fault); the cell goes on.
// Inline in the virtual-time loop (a call and a frame per plugin and tick
// otherwise); the failure path is out of line.
[[gnu::always_inline]] inline void Runtime::step_plugin(const std::string& name, io::Plugin& p,
                                                        TIME dt) {
  try {
    p.step(now_, dt);
  } catch (const std::exception& e) {
    plugin_failed(name, p, e.what());
  } catch (...) {
    plugin_failed(name, p, "an exception that is not a std::exception");
  }
}

void Runtime::plugin_failed(const std::string& name, io::Plugin& p, std::string_view what) {
  std::size_t devices = 0;
  for (const DeviceRuntime& d : devices_) devices += d.plugin == &p;
  const std::string thread = "plugin '" + name + "'";
  report_thread_failure(thread, what);
  p.fail(thread, what, devices);
}

ScanContext Runtime::latch_scan(TaskRuntime& t, TIME now) {
  now_ = now;
  if (t.stopped.load(std::memory_order_relaxed)) return ScanContext{now, t.period, t.cycle};
  const ScanContext ctx = scan_latch(t, now);
  // The halves run apart: another task may latch and merge in between, so
  // this scan merges its changed bits, as in real time (keep its bound
  // bytes as the latch left them).
  if (!t.whole_image_scan && !t.merge_bits) {
    copy_spans(t.keep);
    t.merge_bits = true;
  }
  return ctx;
}

void Runtime::finish_scan(TaskRuntime& t, const ScanContext& ctx) {
  now_ = ctx.now;
  if (!t.stopped.load(std::memory_order_relaxed)) scan_finish(t, ctx);
}

std::uint64_t Runtime::layout_hash() const {
  std::uint64_t h = 1469598103934665603ULL;  // FNV-1a
  auto mix = [&h](const std::string& s) {
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ULL;
    h = (h ^ 0xFF) * 1099511628211ULL;
  };
  for (const auto& t : tasks_) mix(t->name + "/" + std::to_string(t->period.count()));
  for (const auto& d : devices_)
    mix(d.name + "/" + std::to_string(d.in.byte) + "+" + std::to_string(d.sizes.input_bytes) + "/" +
        std::to_string(d.out.byte) + "+" + std::to_string(d.sizes.output_bytes) + "/" +
        std::to_string(d.task));
  return h;
}

void Runtime::set_plugins_enabled(bool on) {
  plugins_enabled_ = on;
  for (auto& t : tasks_) t->plain_fused = on && !t->any_via_plugin;
}

// Whether `t` scans in the tick at `now`: not stopped, and a whole number
// of periods since 0; a task of the base tick's period is due every tick
// (no division then). The virtual-time loop passes the base tick it took.
[[gnu::always_inline]] inline bool Runtime::due_at(const TaskRuntime& t, TIME now, TIME base_tick) {
  return !t.stopped.load(std::memory_order_relaxed) &&
         (t.period == base_tick || now.count() % t.period.count() == 0);
}

bool Runtime::due(const TaskRuntime& t) const { return due_at(t, now_, base_tick_); }

// Whether a task has not stopped: the count that trip() and finish() keep
// as they stop tasks (a task's stopped flag is set nowhere else and never
// cleared), one load instead of a loop over the tasks every tick. Test:
// ScanSemantics.AliveCountFollowsTheStoppedTasks.
[[gnu::always_inline]] inline bool Runtime::any_task_alive() const {
  return tasks_alive_.load(std::memory_order_relaxed) != 0;
}

// Inline in the virtual-time loop, which begins a tick every base tick.
// The step size taken once: a plugin's step() cannot change it (neither
// first_tick_ nor base_tick_ is set outside start() and build), though the
// compiler must assume a virtual call could.
[[gnu::always_inline]] inline void Runtime::begin_tick() {
  if (plugins_enabled_) {
    const TIME dt = first_tick_ ? TIME(0) : base_tick_;
    for (auto& [name, p] : plugins_)
      if (!p->failed()) step_plugin(name, *p, dt);
  }
  first_tick_ = false;
  tick_open_ = true;
  cursor_ = 0;
}

// Moves the cursor to the next task due in the open tick; closes the tick
// (and advances the clock) when none is left.
void Runtime::advance_cursor() {
  while (cursor_ < exec_order_.size() && !due(*exec_order_[cursor_])) ++cursor_;
  if (cursor_ == exec_order_.size()) {
    tick_open_ = false;
    now_ += base_tick_;
  }
}

void Runtime::tick() {
  if (!tick_open_) begin_tick();
  for (advance_cursor(); tick_open_; advance_cursor()) scan(*exec_order_[cursor_++], now_);
}

TaskRuntime* Runtime::step_scan() {
  for (;;) {
    if (!any_task_alive()) return nullptr;
    if (!tick_open_) begin_tick();
    advance_cursor();
    if (!tick_open_) continue;
    TaskRuntime* t = exec_order_[cursor_++];
    scan(*t, now_);
    advance_cursor();
    return t;
  }
}

void Runtime::finish() {
  if (!started_) return;
  stop_watchdog();
  for (auto& t : tasks_) t->stopped.store(true);
  tasks_alive_.store(0, std::memory_order_relaxed);
  {
    MaybeLock lock(image_mutex_, lock_image_);
    apply_safe_outputs(nullptr);
    publish_all();
  }
  if (mode_ == io::ClockMode::Virtual && plugins_enabled_) {
    // Let the devices see the safe outputs once before the plugins stop.
    for (auto& [name, p] : plugins_)
      if (!p->failed()) step_plugin(name, *p, TIME(0));
  }
  if (plugins_enabled_)
    for (auto& [name, p] : plugins_) {
      // Every plugin is stopped, whatever one of them throws.
      try {
        p->stop();
      } catch (const std::exception& e) {
        report_thread_failure("plugin '" + name + "' stop", e.what());
      }
    }
  started_ = false;
}

void Runtime::run(io::ClockMode mode, TIME span) {
  const auto w0 = std::chrono::steady_clock::now();
  start(mode);
  if (mode == io::ClockMode::Virtual) {
    run_virtual(span);
  } else {
    run_realtime(span);
  }
  finish();
  wall_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
}

void Runtime::run_virtual(TIME span) {
  // Saturating: the clock must not run past the end of TIME's int64 range.
  const TIME last = TIME::max() - base_tick_;
  const TIME end = span > last - now_ ? last : now_ + span;
  // begin_tick()'s step size, taken once: only the first tick after start()
  // steps the plugins by 0 (first_tick_ is set by start() alone, cleared by
  // every begin_tick(); a tick that step_scan() left open was begun, so
  // first_tick_ is false then), every later one by base_tick_ (set only at
  // build). begin_tick() would test first_tick_ and load the step every tick.
  TIME dt = first_tick_ ? TIME(0) : base_tick_;
  // Taken once as well (locals, so that no call in the loop makes the
  // compiler load them again): the base tick and the execution order, set
  // at build alone.
  const TIME tick_len = base_tick_;
  TaskRuntime* const* const order = exec_order_.data();
  const std::size_t n = exec_order_.size();
  while (now_ < end && !stop_requested()) {
    if (!any_task_alive()) break;
    if (tick_open_) {
      tick();  // the rest of a tick that step_scan() left open
      continue;
    }
    // tick() as advance_cursor() runs it, with the cursor in a register:
    // each task of the execution order that is due when its turn comes.
    // begin_tick() with the step size above.
    if (plugins_enabled_)
      for (auto& [name, p] : plugins_)
        if (!p->failed()) step_plugin(name, *p, dt);
    dt = tick_len;
    first_tick_ = false;
    tick_open_ = true;
    cursor_ = 0;
    for (std::size_t i = 0; i < n; ++i) {
      TaskRuntime& t = *order[i];
      if (!due_at(t, now_, tick_len)) continue;
      cursor_ = i + 1;
      // scan() with scan_plain() inline.
      if (plain_scans_) [[likely]]
        scan_plain_inline(t, now_);
      else
        scan_hooked(t, now_);
    }
    cursor_ = n;
    tick_open_ = false;
    now_ += tick_len;
  }
}

}  // namespace plc

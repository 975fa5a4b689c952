// The scan engine: tasks, clocks, the global process image, plugins,
// programs and the variable registry of one cell.
//
// One scan of a task, as data (DESIGN.md "One scan, as data"):
//   1 latch the inputs of the devices this task exchanges into the global %I,
//     then copy the global image into the task's private image;
//   2 (forced inputs: debugger)
//   3 run the task's programs in order against the private image;
//   4 (forced outputs: debugger)
//   5 merge the bits the scan changed in %Q and %M back into the global
//     image, then publish the outputs of the devices this task exchanges.
//
// Virtual time: the clock advances by the base tick (the GCD of all task
// periods). At each tick the plugins step first, then every task released
// at that tick runs, in order of priority (0 = highest), ties in config
// order. Nothing sleeps; a run is reproducible bit for bit.
//
// Real time: one thread per task, CLOCK_MONOTONIC absolute sleeps to the
// release times t0 + k*period, SCHED_FIFO where permitted. A scan that ends
// after its next release counts an overrun and the missed releases are
// skipped (never run back to back). A watchdog thread stops a task whose
// scan exceeds `watchdog` x period and puts its outputs to their safe values.
//
// Watchdog in virtual time: a scan has no duration in virtual time, so the
// watchdog there catches runaway programs by the CPU time the scan thread
// spends in one scan (not wall time, which a busy machine stretches by
// preempting us: that would make a reproducible run trip at random), and
// only above kVirtualWatchdogFloorNs whatever `watchdog` x period is. CPU time
// is not free of the machine either: in a VM the host's delays inside a
// system call, an IPI or a page fault are charged to the thread (a recorded
// demo scan waiting for the writer took 1-3 ms of CPU here, one scan of an
// ASan build on CI 11 ms), so a limit of a few periods stopped reproducible
// runs at random, and a program near its budget would stop on one machine
// and not on another. The watchdog thread requests the stop; the scan
// thread applies it when the scan returns.
#pragma once

#include <time.h>

#include <array>
#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "plc/cell_config.hpp"
#include "plc/io/plugin.hpp"
#include "plc/io/process_image.hpp"
#include "plc/pi_mutex.hpp"
#include "plc/program.hpp"
#include "plc/task_stats.hpp"
#include "plc/var_registry.hpp"

namespace plc {

class CellLibrary;   // plc/cell_library.hpp
class OnlineChange;  // plc/online_change.hpp
struct ProgramSwap;  // plc/online_change.hpp
struct TaskThread;   // a real-time task thread's record (runtime/src/task_thread.hpp)

struct DeviceRuntime {
  std::string name;
  std::string plugin_name;
  io::Plugin* plugin = nullptr;
  std::size_t index = 0;  // within its plugin
  io::DeviceSizes sizes;
  io::IecAddress in{io::Area::Input, io::AddrSize::Byte, 0, 0};
  io::IecAddress out{io::Area::Output, io::AddrSize::Byte, 0, 0};
  int task = -1;                   // the task that exchanges its data
  io::DeviceLink* link = nullptr;  // plugin->link(index), the same object for the plugin's life
  // plugin->direct_io(index) at start: the scan copies from and to these
  // bytes itself (empty: it calls latch_inputs()/publish_outputs()).
  const std::uint8_t* direct_in = nullptr;
  std::uint8_t* direct_out = nullptr;
};

// A span of one image area, [begin, end) in bytes.
struct ImageRange {
  std::uint32_t begin = 0, end = 0;
};
// One range of bytes a scan copies or merges, with its pointers resolved
// at build (the images never move): to `dst` from `src`; for a merge, the
// task's copy at the latch is `before`.
struct ImageSpan {
  std::uint8_t* dst = nullptr;
  const std::uint8_t* src = nullptr;
  const std::uint8_t* before = nullptr;
  std::size_t n = 0;
};

struct TaskRuntime {
  std::string name;
  TIME period{};
  int priority = 0;
  double watchdog = 0;  // multiple of the period, 0 = off
  std::size_t order = 0;
  std::vector<Program*> programs;
  std::vector<std::string> program_names;
  io::ProcessImage image, before;       // private copy; its %Q/%M at scan start
  std::vector<DeviceRuntime*> devices;  // exchanged by this task
  std::vector<std::uint8_t> owned_q;    // bit mask of the %Q bits this task writes
  // The image bytes this task's programs can reach (their located variables
  // and device ports), per area (io::Area), sorted and coalesced; computed
  // at build. A scan copies in and merges back only these, unless a hook
  // may write anywhere in the images (ScanHooks::whole_image).
  std::array<std::vector<ImageRange>, 3> bound;
  // bound as the scan uses it: the latch copies global -> image (copy_in),
  // real time keeps image -> before (keep) and merges into global the bits
  // changed since (merge_out); virtual time copies image -> global (copy_out).
  std::vector<ImageSpan> copy_in, keep, copy_out, merge_out;
  // The devices' bytes as the scan exchanges them (Runtime::plan_device_io,
  // at build and at start): `direct` the devices whose bytes the scan copies
  // itself (Plugin::direct_io, virtual time), with their image and device
  // pointers resolved, in one flat list; `via_plugin` the others, whose
  // plugin latches and publishes them, with their image bytes resolved too
  // (no pointer for no bytes: that way is skipped). Both in `devices` order.
  struct DirectDevice {
    std::uint8_t* image_in;
    const std::uint8_t* device_in;
    std::size_t in_bytes;
    std::uint8_t* device_out;
    const std::uint8_t* image_out;
    std::size_t out_bytes;
  };
  struct PluginDevice {
    io::Plugin* plugin;
    std::size_t index;  // within its plugin
    std::uint8_t* image_in;
    std::size_t in_bytes;
    const std::uint8_t* image_out;
    std::size_t out_bytes;
  };
  std::vector<DirectDevice> direct;
  std::vector<PluginDevice> via_plugin;
  bool any_via_plugin = false;  // !via_plugin.empty(), in one load
  // The plain scan's copies while every device is direct (no via_plugin):
  // the devices' inputs, then copy_in; copy_out, then the devices'
  // outputs; one loop each (Runtime::plan_device_io).
  std::vector<ImageSpan> plain_in, plain_out;
  bool plain_fused = false;  // the plugins on and every device direct: plain_in, plain_out used
  bool whole_image_scan = false;  // this scan copies and merges whole areas (set at its latch)
  // This scan merges the bits it changed (kept in `before` at its latch)
  // instead of copying its bound bytes back: in real time, and for halves
  // driven apart (latch_scan/finish_scan), where another task's scan may
  // have written the global image between this latch and this merge.
  bool merge_bits = false;
  std::uint32_t timing_phase =
      0;  // virtual time: untimed scans before the next timed one (Runtime::timed_now)
  bool scan_timed = false;  // the scan under way is timed
  LiveTaskStats stats;      // recorded by the task's thread; snapshot() from any
  std::atomic<bool> stopped{false};
  // Real time: set from before the task looks at the pause flag until its
  // scan is over, so that once the pause is set and this is seen clear, the
  // task is at its next release and everything its scans wrote is visible
  // (Runtime::wait_until_idle).
  std::atomic<bool> busy{false};
  std::atomic<std::int64_t> scan_started_ns{-1};  // steady/monotonic ns (0: not timed), -1 = idle
  std::atomic<std::uint64_t> scan_seq{0};         // scans started (watchdog bookkeeping)
  // Virtual time: the watchdog thread asks, the scan thread stops the task
  // when the scan returns (so the image is only ever touched by one thread).
  std::atomic<bool> trip_requested{false};
  std::string trip_reason;
  std::atomic<std::int64_t> step_budget{0};  // real time: scans allowed while paused
  std::uint64_t cycle = 0;
  // Runtime::state_changes_ as this task's last latch of its devices'
  // states read it (before latching them); never a count at first.
  std::uint64_t latched_changes = ~std::uint64_t{0};
  TIME scan_time{};  // ScanContext::now of the scan under way (set before its latch)
  // Online change: applied by this task's thread at its next scan start.
  std::atomic<ProgramSwap*> swap{nullptr};
};

// Called after every scan of every task, in the scan's thread (trace,
// debugger, HMI snapshot). Must be quick and must not block.
using ScanObserver = std::function<void(const TaskRuntime&, const ScanContext&)>;

// Told of every online change of the runtime's programs, by the change
// itself (OnlineChange::prepare), so that no caller can forget one: what
// points into the programs (the retain manager's layout) must follow every
// change, or it reads programs that the change destroys.
class ChangeObserver {
 public:
  virtual ~ChangeObserver() = default;
  // In prepare(), once the change can be applied, before it is committed
  // (OnlineChange::follow subscribes to its switch). May throw: the change
  // is then refused with the reason.
  virtual void follow(OnlineChange& change) = 0;
};

// Points inside a scan where the debugger (forcing, writes, freeze points,
// recording and replay) acts. All run in the scan's thread; the two that get
// the global image run under the image lock. A recording compares, at a
// scan's merge, only the %Q/%M words the scan can have changed (the task's
// bound bytes and the debugger's writes, which it is told of: Debugger::
// apply_write), and the whole image after a stop or an online change: a
// new hook that writes image bytes must tell the recorder too
// (Recorder::note_write), or the recording's output hash misses them and
// its replay reports a difference.
class ScanHooks {
 public:
  virtual ~ScanHooks() = default;
  // Whether this hook set may write image bytes that no program of the task
  // is bound to, or reads the task's private image outside them: then the
  // scans copy and merge the whole %I/%Q/%M areas while it is added (forces
  // and writes of any address, recording, replay). One that neither writes
  // image bytes nor reads a task's private image outside the bound bytes
  // may return false: the retain manager does (it reads the global image
  // only, after the merge).
  [[nodiscard]] virtual bool whole_image() const { return true; }
  // 1b: the task's devices are latched into the global image (forced inputs,
  // recording, replay).
  virtual void after_latch(TaskRuntime&, io::ProcessImage& /*global*/) {}
  // 1a: an answer to an acyclic request of this task became visible at this
  // latch (device = index in Runtime::devices()); before after_latch.
  virtual void on_answer(TaskRuntime&, std::size_t /*device*/, const io::RecordRequest&) {}
  // 2: the private copy is taken, programs not yet run (writes, forces).
  virtual void before_programs(TaskRuntime&, const ScanContext&) {}
  // 3a: before program `index` of the task runs (freeze points).
  virtual void before_program(TaskRuntime&, std::size_t /*index*/, const ScanContext&) {}
  // 4: programs done, nothing merged yet (forces on program variables).
  virtual void after_programs(TaskRuntime&, const ScanContext&) {}
  // 5b: merged into the global image, not yet published (forced outputs).
  virtual void before_publish(TaskRuntime&, io::ProcessImage& /*global*/) {}
  // The task was stopped (watchdog, fault) and its outputs were just put to
  // their safe values; under the image lock, in the thread that stopped it.
  virtual void on_stop(TaskRuntime&, io::ProcessImage& /*global*/) {}
};

// The longest run plcrun accepts (--for, --cycles): 100 years. With periods
// of at most a day (kMaxPeriod) the clock then never comes near the end of
// TIME's int64 nanoseconds (292 years).
inline constexpr TIME kMaxRunSpan = std::chrono::hours(24 * 36500);

class Runtime {
 public:
  // Virtual time steps the devices at every base tick, also at ticks where
  // no task is due, because their dynamics (ramps, filters, noise drawn per
  // step, communication watchdogs) depend on the step size: advancing them
  // in one jump to the next release would change results. So the clock may
  // take at most this many base ticks from one release of the fastest task
  // to the next. Sensible period sets need 1 to 10 (1ms/10ms, 2ms/3ms,
  // 4ms/6ms); 1h and 1h1us would need 3.6e9 device steps per scan, which
  // looks like a hang.
  static constexpr std::int64_t kMaxTicksPerRelease = 1000;
  // Virtual time times one scan in this many for the statistics (every scan
  // is counted); real time times every scan.
  static constexpr std::uint32_t kVirtualTimedEvery = 64;
  // Virtual time: the least CPU time of one scan that the watchdog stops
  // (see the top of this file). Half a second: far above any noise seen,
  // and a runaway program still stops at once for a person watching.
  static constexpr std::int64_t kVirtualWatchdogFloorNs = 500'000'000;

  // Builds the whole cell; throws ConfigError naming file:line:column.
  explicit Runtime(const CellConfig& cfg);
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;

  // Runs for `span` of time (virtual or real) or until request_stop().
  // Ends with every output at its safe value.
  void run(io::ClockMode mode, TIME span);
  // Async-signal-safe: asks run() to stop at the next tick/scan boundary.
  void request_stop() { stop_requested_.store(true, std::memory_order_relaxed); }
  [[nodiscard]] bool stop_requested() const {
    return stop_requested_.load(std::memory_order_relaxed);
  }

  // Fine-grained virtual-time control (tests, debugger): start() the
  // plugins, tick() one base tick at a time, finish() to go safe and stop.
  // start(Virtual) throws virtual_clock_error() when there is one.
  void start(io::ClockMode mode);
  void tick();
  // Virtual time: run exactly the next due scan (stepping the devices first
  // when a new tick begins); returns its task, or nullptr when every task
  // has stopped. Ticks are closed eagerly, so between calls now() is the
  // time of the next scan.
  TaskRuntime* step_scan();
  void finish();

  // Real time: pause the logic at scan boundaries. While paused the tasks
  // do not scan (no latch, no programs, no publish) and the plugins go on
  // exchanging the last outputs, so devices do not time out. allow_scans()
  // lets a paused task run n more scans (stepping).
  void set_paused(bool p) { paused_.store(p); }  // seq_cst: see TaskRuntime::busy
  [[nodiscard]] bool paused() const { return paused_.load(std::memory_order_acquire); }
  void allow_scans(TaskRuntime& t, std::int64_t n) {
    t.step_budget.fetch_add(n, std::memory_order_acq_rel);
  }
  // Real time: waits, at most `timeout`, until no task is inside a scan; true
  // when none is. After set_paused(true) (and no step budget left) the logic
  // has then stopped, and the caller sees everything the scans wrote: it may
  // read the tasks' variables until it resumes them. Virtual time: true.
  bool wait_until_idle(std::chrono::nanoseconds timeout) const;

  // Several hook sets may be active (debugger, recorder, replayer); they run
  // in the order they were added.
  void add_hooks(ScanHooks* h) {
    hooks_.push_back(h);
    plain_scans_ = false;
    whole_image_hooks_ += h->whole_image() ? 1 : 0;
  }
  void remove_hooks(ScanHooks* h);
  // Replay of a recording, which fixes the order and times of the scans
  // itself: one scan of `t` at time `now` outside the virtual schedule, in
  // its two image-locked halves, so that the scans of several tasks
  // interleave as they did in real time. latch_scan() is step 1 (latch, the
  // private copy); finish_scan() steps 2-5 (programs, merge, publish) with
  // the context latch_scan() returned. Nothing happens for a stopped task.
  ScanContext latch_scan(TaskRuntime& t, TIME now);
  void finish_scan(TaskRuntime& t, const ScanContext& ctx);
  // Replay: stops a task as its watchdog or a fault did in the recording
  // (outputs to their safe values).
  void stop_task(TaskRuntime& t, const std::string& reason) { trip(t, reason, false); }
  // A hash of the cell's layout (tasks, devices and their addresses) that a
  // recording must match to be replayed on it.
  [[nodiscard]] std::uint64_t layout_hash() const;
  // Replay: devices are neither stepped, latched nor published; inputs come
  // from the hooks (after_latch) instead.
  void set_plugins_enabled(bool on);

  [[nodiscard]] TIME now() const { return now_; }
  [[nodiscard]] TIME base_tick() const { return base_tick_; }
  [[nodiscard]] TIME fastest_period() const { return fastest_period_; }
  // Why the virtual clock cannot run this cell (too many base ticks per
  // release, see kMaxTicksPerRelease), located at the task period that
  // causes it; empty when it can. Real time is not affected.
  [[nodiscard]] const std::optional<ConfigError>& virtual_clock_error() const {
    return virtual_clock_error_;
  }
  [[nodiscard]] io::ClockMode mode() const { return mode_; }

  VarRegistry& vars() { return vars_; }
  [[nodiscard]] const VarRegistry& vars() const { return vars_; }
  [[nodiscard]] const std::vector<std::unique_ptr<TaskRuntime>>& tasks() const { return tasks_; }
  [[nodiscard]] const TaskRuntime* task(const std::string& name) const;
  io::ProcessImage& image() { return global_; }
  [[nodiscard]] io::ByteOrder byte_order() const { return order_; }
  io::Plugin* plugin(const std::string& name);
  Program* program(const std::string& name);
  [[nodiscard]] const std::vector<DeviceRuntime>& devices() const { return devices_; }
  // The cell libraries (`libraries:`), in their current builds.
  [[nodiscard]] const std::vector<std::shared_ptr<CellLibrary>>& libraries() const {
    return libraries_;
  }
  [[nodiscard]] const std::string& cell_name() const { return cell_name_; }

  void add_scan_observer(ScanObserver o) {
    observers_.push_back(std::move(o));
    any_observer_ = true;
  }
  // Every online change of this runtime tells `o` (ChangeObserver); it
  // must be removed before it goes.
  void add_change_observer(ChangeObserver* o) { change_observers_.push_back(o); }
  void remove_change_observer(ChangeObserver* o) { std::erase(change_observers_, o); }
  // Runs f() with the global image locked against the tasks' latch and
  // merge (real time; in virtual time nothing runs concurrently).
  template <class F>
  void with_image_locked(F&& f) {
    if (!lock_image_) return f();
    image_mutex_.lock();
    f();
    image_mutex_.unlock();
  }

  // Per-task statistics as JSON (plcrun --stats-json).
  [[nodiscard]] std::string stats_json() const;
  // Wall-clock seconds spent inside run() (for the virtual/real speed ratio).
  [[nodiscard]] double wall_seconds() const { return wall_seconds_; }
  // Why the runtime stopped the cell itself ("" = it did not): its
  // watchdog thread failed (plc/thread_guard.hpp). Read after run().
  [[nodiscard]] const std::string& failure() const { return failure_; }

 private:
  void build(const CellConfig& cfg);
  friend class OnlineChange;  // replaces programs at scan boundaries (plc/online_change.hpp)
  // false: the run left this real-time task thread behind inside a program
  // (TaskThread), and it must return without touching the runtime.
  bool scan(TaskRuntime& t, TIME now);  // scan_plain() or scan_hooked()
  bool scan_hooked(TaskRuntime& t, TIME now);
  void scan_failed(TaskRuntime& t, std::string_view what);
  void step_plugin(const std::string& name, io::Plugin& p, TIME dt);
  ScanContext scan_latch(TaskRuntime& t, TIME now);          // step 1
  bool scan_finish(TaskRuntime& t, const ScanContext& ctx);  // steps 2-5
  void trip(TaskRuntime& t, const std::string& reason, bool watchdog);
  void apply_safe_outputs(const std::vector<std::uint8_t>* mask);
  void publish_all();
  void run_virtual(TIME span);
  void run_realtime(TIME span);
  void realtime_task_loop(TaskRuntime& t, std::int64_t t0_ns);
  void watchdog_loop();
  void start_watchdog();
  void stop_watchdog();

  // First, so destroyed last: the programs, plugins and models below run
  // code from these libraries.
  std::vector<std::shared_ptr<CellLibrary>> libraries_;
  // Builds of an online change that switched only some tasks (a timeout):
  // those tasks run them until the runtime goes (OnlineChange::finish).
  std::vector<std::shared_ptr<CellLibrary>> partial_libraries_;
  std::string cell_name_;
  io::ByteOrder order_ = io::ByteOrder::Big;
  io::ProcessImage global_;
  std::vector<std::uint8_t> safe_q_;
  // How many devices' links track a request (DeviceLink::set_deferred):
  // while none does, a latch skips looking at every link. Before plugins_,
  // whose links point here, so that it outlives them.
  std::atomic<std::uint32_t> links_tracking_{0};
  // How many state changes the devices' links made (DeviceLink::set_state):
  // a latch skips the links' states while it equals its task's
  // TaskRuntime::latched_changes. Here for the same reason.
  std::atomic<std::uint64_t> state_changes_{0};
  std::vector<std::pair<std::string, std::unique_ptr<io::Plugin>>> plugins_;
  std::vector<std::pair<std::string, std::unique_ptr<Program>>> programs_;
  // The old programs such a partial change replaced: a reader that followed
  // the old layout (retain) may still read them; no task runs them.
  std::vector<std::unique_ptr<Program>> retired_programs_;
  std::map<std::string, std::string> program_types_;  // program name -> type
  // program name -> (field path -> address or device) from the config's bind:
  std::map<std::string, std::map<std::string, std::string>> program_binds_;
  std::vector<DeviceRuntime> devices_;
  std::vector<std::unique_ptr<TaskRuntime>> tasks_;
  std::vector<TaskRuntime*> exec_order_;  // by priority, then config order
  // The tasks not stopped (any_task_alive()): trip() and finish() count
  // down as they set TaskRuntime::stopped (the watchdog's thread trips in
  // real time, hence atomic).
  std::atomic<std::size_t> tasks_alive_{0};
  VarRegistry vars_;
  std::vector<ScanObserver> observers_;
  bool any_observer_ = false;  // !observers_.empty(), in one load
  std::vector<ChangeObserver*> change_observers_;
  std::vector<ScanHooks*> hooks_;
  std::size_t whole_image_hooks_ = 0;  // hooks_ whose whole_image() is true
  bool plugins_enabled_ = true;
  std::atomic<bool> paused_{false};
  bool tick_open_ = false;
  std::size_t cursor_ = 0;  // next entry of exec_order_ in the open tick
  void begin_tick();
  void advance_cursor();
  void plan_device_io();
  bool run_programs_and_publish(TaskRuntime& t, const ScanContext& ctx);
  // Virtual time with no hook set added (the usual run): the scan that
  // scan_latch() and run_programs_and_publish() make then, in one function
  // without the hook loops, the image lock, the whole-image and merge
  // branches and a second frame, which such a scan pays for and never uses
  // (test: ScanSemantics.PlainScanEqualsHookedScan).
  bool scan_plain(TaskRuntime& t, TIME now);
  bool scan_plain_inline(TaskRuntime& t, TIME now);
  // Parts both scans share: step 1's devices (latch, answers, states) and
  // step 5's (publish); deliver_answers() is 1a, while a link tracks a request.
  void latch_devices(TaskRuntime& t, TIME now);  // latch_device_bytes(), latch_states()
  void latch_device_bytes(TaskRuntime& t);
  void latch_states(TaskRuntime& t, TIME now);
  void deliver_answers(TaskRuntime& t);
  void publish_devices(TaskRuntime& t);
  // What step_plugin() does when the plugin throws (out of line: rare).
  void plugin_failed(const std::string& name, io::Plugin& p, std::string_view what);
  [[nodiscard]] bool due(const TaskRuntime& t) const;
  [[nodiscard]] static bool due_at(const TaskRuntime& t, TIME now, TIME base_tick);
  static bool timed_now(TaskRuntime& t);
  [[nodiscard]] bool any_task_alive() const;

  io::ClockMode mode_ = io::ClockMode::Virtual;
  bool started_ = false;
  bool first_tick_ = true;
  TIME now_{};
  TIME base_tick_{};
  TIME fastest_period_{};
  std::optional<ConfigError> virtual_clock_error_;
  PiMutex image_mutex_;
  bool lock_image_ = false;  // only real time has concurrent tasks
  // !lock_image_ && hooks_.empty(), kept by start(), add_hooks() and
  // remove_hooks(): scan() takes scan_plain() (one load per scan).
  bool plain_scans_ = true;
  std::atomic<bool> stop_requested_{false};
  std::atomic<bool> rt_running_{false};
  std::atomic<bool> watchdog_running_{false};
  std::thread watchdog_thread_;
  // Real time: task threads that a run left inside a runaway program; the
  // destructor hands them what they may still touch (TaskThread).
  std::vector<std::shared_ptr<TaskThread>> left_behind_;
  void hand_over_left_behind();
  clockid_t scan_thread_cpu_clock_{};  // virtual time: the thread that calls tick()
  double wall_seconds_ = 0;
  std::string failure_;  // written by the failing watchdog thread before its stop request
};

}  // namespace plc

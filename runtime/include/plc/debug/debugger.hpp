// The debugger's command layer: run control, breakpoints, watch, write and
// force, trace, record/replay and goto. The typed API (read, write, force,
// unforce, pause, step, continue_running, run_until, add_breakpoint,
// delete_breakpoint) holds each command's semantics; execute() is the text
// front end over it, used by the console (plcrun --debug) and command files
// (--commands); the HMI bridge (hmi-bridge/) is another front end.
//
// Virtual time: the debugger drives the scans itself; the cell starts paused
// before its first scan, and the simulated devices stop with the clock.
// Real time: the runtime runs in its own thread; pausing holds the tasks at
// their next release while the fieldbus plugins keep exchanging the last
// outputs, so devices do not time out.
//
// Forcing follows CODESYS: `write` sets a value once, at the start of the
// next scan of the variable's task; `force` sets it every scan until
// `unforce` (keeping the value, or restoring the one from before the force):
// forced inputs are applied after the inputs are latched, forced outputs
// and memory at the start of the scan and again before they are published,
// forced program variables at the start and at the end of their task's scan.
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "plc/debug/condition.hpp"
#include "plc/debug/recording.hpp"
#include "plc/debug/trace.hpp"
#include "plc/runtime.hpp"

namespace plc::retain {
class Manager;  // plc/retain/retain_manager.hpp
}

namespace plc::debug {

class Debugger final : public ScanHooks {
 public:
  using Factory = std::function<std::unique_ptr<Runtime>()>;
  using Reader = std::function<std::optional<std::string>(const std::string& prompt)>;
  using Writer = std::function<void(const std::string&)>;

  struct Options {
    io::ClockMode mode = io::ClockMode::Virtual;
    std::string replay_file;                  // replay this recording instead of the plugins
    TIME span{std::chrono::hours(24 * 365)};  // end of the session (virtual time)
    // Record into this file from the first scan (plcrun --record): armed
    // before the cell starts, which a `record` command cannot be in real
    // time. Throws std::runtime_error if the file cannot be written.
    std::string record_file;
    // Called with every runtime the debugger builds (also on goto and
    // restart), before its first scan: where a front end such as the HMI
    // bridge adds its scan observers.
    std::function<void(Runtime&)> on_build;
  };

  // `factory` builds a fresh runtime of the cell (goto rebuilds with it).
  // Throws std::runtime_error for a recording that cannot be replayed.
  Debugger(Factory factory, Options options);
  ~Debugger() override;

  // Runs one command line and returns what it prints.
  std::string execute(std::string_view line);

  // ---- The typed API. Every call (and execute) holds session_mutex(), so
  // front ends on different threads (console, HMI bridge) take turns.
  struct Reply {
    bool ok = true;    // false: refused or failed, nothing changed
    std::string text;  // what the console prints for it
  };
  // A variable's value as its program saw it in its last scan (read
  // consistently, see read_values); `image` is the global image's value of a
  // located variable when it differs (a force or another task changed it).
  struct Value {
    std::string name, error;  // error set: no value
    VarType type = VarType::BOOL;
    std::optional<io::IecAddress> address;
    std::string text, image;  // IEC notation
    bool forced = false;
  };
  std::vector<Value> read(const std::vector<std::string>& names);
  // The same as raw values in native storage (read() formats these): for a
  // front end that formats them itself (the HMI host hands them to the
  // bridge's process).
  struct TypedValue {
    std::string name, error;  // error set: not a variable (nothing else set)
    std::string no_value;     // set: a variable, but no consistent value now (bytes unset)
    VarType type = VarType::BOOL;
    std::optional<io::IecAddress> address;
    alignas(8) unsigned char bytes[sizeof(STRING)] = {};
    bool image_differs = false;  // a located variable whose global image value differs
    alignas(8) unsigned char image[8] = {};
    bool forced = false;
  };
  std::vector<TypedValue> read_typed(const std::vector<std::string>& names);
  // Once, at the start of the next scan of the variable's task.
  Reply write(const std::string& name, std::string_view value);
  // Every scan until unforce.
  Reply force(const std::string& name, std::string_view value);
  // write and force with the value as bytes in native storage of the
  // variable's type (from a front end that parsed the literal itself, the
  // HMI bridge's process): the same checks as the text path, i.e. read-only
  // state and STRING refused, the bytes a value of the type
  // (check_raw_value: a BOOL 0 or 1, a finite REAL), the block's write check.
  Reply write_raw(const std::string& name, const void* value);
  Reply force_raw(const std::string& name, const void* value);
  // name "all": every force; restore: write back the value from before it.
  Reply unforce(const std::string& name, bool restore);
  // The names of the variables forced now, as they were given to force.
  std::vector<std::string> forced();
  // Every force whose name (as it was forced) `release` accepts, in one
  // step: no scan sees some of them released and others not. The others
  // stay, value and all. Refused when it releases nothing. The HMI bridge's
  // `unforce all`: only what its forceable patterns match.
  Reply unforce_if(const std::function<bool(const std::string& name)>& release, bool restore);
  Reply pause();
  // n scans of each task, or of `task` only.
  Reply step(std::uint64_t n = 1, const std::string& task = "");
  // Real time: returns at once (running); virtual time: runs until a
  // breakpoint, the end of the span, or `for_time`.
  Reply continue_running(std::optional<TIME> for_time = std::nullopt);
  Reply run_until(std::string_view condition);
  // A scan-end breakpoint on `condition`, or a freeze point before program
  // `before_program` (optionally filtered by `condition`); stops on every
  // `hits`-th hit.
  Reply add_breakpoint(std::string_view condition, std::uint64_t hits = 1,
                       const std::string& before_program = "");
  // A scan-end breakpoint on a condition compiled elsewhere (the HMI
  // bridge's process, plc/debug/condition_code.hpp): validated and bound
  // (Condition::bind), never parsed; listed with the text made from it.
  Reply add_breakpoint(ConditionCode code, std::vector<ConditionOperand> operands,
                       std::uint64_t hits = 1);
  Reply delete_breakpoint(const std::string& id_or_all);
  // Held by every call above; a front end on another thread may try_lock
  // it (a bounded number of times) to answer "busy" instead of waiting
  // behind a long `run until`. Not a timed mutex: ThreadSanitizer does not
  // intercept pthread_mutex_clocklock and would report every unlock.
  std::recursive_mutex& session_mutex() { return session_mu_; }

  [[nodiscard]] bool quit_requested() const { return quit_; }
  [[nodiscard]] std::string prompt() const;
  // Async-signal-safe: interrupts a running `continue`, `run until`, `step`
  // or `goto` (Ctrl-C at the console); the session goes on.
  void interrupt() { interrupted_.store(true, std::memory_order_relaxed); }
  // Async-signal-safe: ends the session (SIGTERM; Ctrl-C without a
  // console). A running command stops at the next scan boundary and no
  // further scan runs; the front end then stops reading commands, and
  // destroying the debugger puts the outputs to their safe values.
  void request_end() {
    end_requested_.store(true, std::memory_order_relaxed);
    interrupted_.store(true, std::memory_order_relaxed);
  }
  [[nodiscard]] bool end_requested() const {
    return end_requested_.load(std::memory_order_relaxed);
  }
  // Stops the cell for good: joins the real-time tasks or finishes the
  // virtual run; every output goes to its safe value. runtime() stays
  // readable (statistics for a summary).
  void stop_cell();
  // Where nested command loops (freeze points) read and print.
  void set_io(Reader r, Writer w) {
    reader_ = std::move(r);
    writer_ = std::move(w);
  }

  Runtime& runtime() { return *rt_; }
  [[nodiscard]] std::uint64_t scan_count() const { return last_scan().scans; }
  // The retain manager of the running cell (plcrun, a session that loads
  // and saves retain data: one that never rebuilds its runtime), or null:
  // `reload` switches its file layout with the programs.
  void set_retain(retain::Manager* m) { retain_ = m; }

  // ScanHooks. A recording started with `record` gets them from here, after
  // the debugger's own work (so it sees the writes and forces it records),
  // under mu_: it can start and stop while real-time tasks run.
  void after_latch(TaskRuntime& t, io::ProcessImage& global) override;
  void on_answer(TaskRuntime& t, std::size_t device, const io::RecordRequest& r) override;
  void before_programs(TaskRuntime& t, const ScanContext& ctx) override;
  void before_program(TaskRuntime& t, std::size_t index, const ScanContext& ctx) override;
  void after_programs(TaskRuntime& t, const ScanContext& ctx) override;
  void before_publish(TaskRuntime& t, io::ProcessImage& global) override;
  void on_stop(TaskRuntime& t, io::ProcessImage& global) override;

 private:
  struct Breakpoint {
    int id = 0;
    std::string text;                        // as typed, for rebuilds and listing
    std::optional<Condition> cond;           // scan-end condition (or freeze filter)
    int task = -1;                           // evaluate after this task's scans (-1: every scan)
    std::string before_program;              // freeze point: before this program ("" = scan end)
    std::uint64_t hits = 0, hit_target = 1;  // stop on every hit_target-th hit
    bool temporary = false;                  // `run until`
  };
  struct Force {
    std::string name;    // as typed
    VarInfo var;         // program variable, or image address in the global image
    bool image = false;  // located/address force
    std::uint64_t value = 0, original = 0;
  };
  struct Write {
    std::string name;
    VarInfo var;
    bool image = false;
    std::uint64_t value = 0;
    int task = -1;
  };

  // (Re)creates the runtime and re-resolves everything; `before_start` runs
  // on the new runtime before its first scan (restart's retained values).
  void build(const std::function<void(Runtime&)>& before_start = {});
  void attach();
  void detach();
  std::string cmd_step(const std::vector<std::string>& a);
  std::string cmd_continue(const std::vector<std::string>& a, bool until);
  std::string cmd_break(const std::vector<std::string>& a);
  std::string cmd_print(const std::vector<std::string>& a);
  std::string cmd_write(const std::vector<std::string>& a, bool force);
  std::string cmd_unforce(const std::vector<std::string>& a);
  std::string cmd_trace(const std::vector<std::string>& a);
  std::string cmd_record(const std::vector<std::string>& a);
  std::string cmd_goto(const std::vector<std::string>& a);
  std::string cmd_restart(const std::vector<std::string>& a);
  std::string cmd_reload(const std::vector<std::string>& a);  // online change (reload.cpp)
  std::string cmd_stats();
  std::string cmd_watch(const std::vector<std::string>& a, bool add);
  std::string help() const;
  Reply run_and_report(std::optional<TIME> for_time, bool until);
  Reply write_or_force(const std::string& name, std::string_view text, bool force);
  Reply write_or_force_raw(const std::string& name, const void* value, bool force);
  // After the checks: queues the write or sets the force (session_mu_ held).
  Reply apply_write_or_force(const std::string& name, const VarInfo& v, bool image,
                             std::uint64_t value, bool force);
  std::string stop_report(const std::string& why);
  std::string watch_lines();
  std::string forces_list();
  std::string breaks_list();

  // Resolves a path or an IEC address; error in `err`.
  std::optional<VarInfo> resolve(const std::string& name, bool& image, std::string& err);
  // Virtual time: run one scan (live or replayed); false when nothing can run.
  bool one_scan();
  // A write into t's scan, noted by a running recording (mu_ held).
  void apply_write(TaskRuntime& t, const VarInfo& v, const void* value);
  // After every scan, on its thread: counters, reads, trace row, conditions.
  // In real time only the finishing task's variables are settled, and the
  // global image is only readable under the image lock (one_task.hpp):
  // on_scan_end takes that lock (before mu_) when a condition or the trace
  // reads the image, and scan_end() then gets global_readable.
  void on_scan_end(const TaskRuntime& t, const ScanContext& ctx);
  void scan_end(const TaskRuntime& t, const ScanContext& ctx, bool global_readable);
  // Whether a breakpoint or the running trace reads the global image; kept
  // up to date (mu_ held) by every change to breaks_ and the trace. A scan
  // that looked before a change skips what it cannot read, for that scan.
  std::atomic<bool> scan_end_reads_global_{false};
  void note_scan_end_reads();
  // Real time: "" when condition c reads variables of one task only
  // (one_task.hpp), else why it is refused.
  [[nodiscard]] std::string realtime_condition_error(const Condition& c) const;
  void freeze_if_due(TaskRuntime& t, std::size_t index);  // a freeze point before program `index`
  void freeze_loop(TaskRuntime& t, std::size_t index);
  // Real time: waits for a breakpoint or Ctrl-C, or until `span` of real
  // time has passed (`continue for`), then pauses; the stop reason.
  std::string realtime_wait_until_paused(std::optional<TIME> span = std::nullopt);
  // A trace over `vars` set up as trace_spec_ says (build(), and reload
  // for the new program's registry).
  [[nodiscard]] std::unique_ptr<Trace> make_trace(const VarRegistry& vars) const;

  Factory factory_;
  Options opt_;
  std::recursive_mutex session_mu_;
  std::unique_ptr<Runtime> rt_;
  std::unique_ptr<Replayer> replayer_;
  std::unique_ptr<Recorder> recorder_;
  std::unique_ptr<Trace> trace_;
  std::vector<std::string> trace_spec_;  // trace add/trigger/pre, replayed on rebuild
  std::vector<Breakpoint> breaks_;
  std::vector<Force> forces_;
  std::vector<Write> writes_;
  std::vector<std::string> watches_;
  // The tables above and the scan counters below, shared with real-time scan
  // threads. Lock order: the runtime's image lock before mu_ (the hooks that
  // run under the image lock take mu_), never the other way round.
  mutable std::mutex mu_;
  std::thread rt_thread_;
  int next_break_id_ = 1;
  // Counted at the end of every scan (mu_). The task is an index, not a
  // name: a scan thread must not allocate.
  struct LastScan {
    std::uint64_t scans = 0;
    TIME time{};
    int task = -1;
  };
  LastScan last_;
  [[nodiscard]] LastScan last_scan() const;  // a copy, taken under mu_
  std::string describe_value(const std::string& name);
  std::string describe_values(const std::vector<std::string>& names);
  // The values of `vars`, formatted, each read where it is consistent: in
  // real time, while the tasks run, a task's variables are copied by its
  // scan thread at the end of one scan (all of them from the same scan) and
  // the global image under the image lock, so no value is ever torn and
  // variables of one task never mix two scans.
  std::vector<std::string> read_values(const std::vector<VarInfo>& vars);
  // The same as raw values (native layout, as VarRegistry::read gives them);
  // `error` says why a value could not be read consistently (a task that
  // stays inside a scan): then `bytes` hold no value.
  struct RawValue {
    alignas(8) unsigned char bytes[sizeof(STRING)];
    std::string error;
  };
  std::vector<RawValue> read_raw(const std::vector<VarInfo>& vars);
  // Real time: nothing writes the variables of task t now (it is held by the
  // pause or stopped, and not inside a scan), so they may be read directly.
  // Virtual time: always.
  [[nodiscard]] bool task_quiet(const TaskRuntime& t) const;
  void serve_reads(const TaskRuntime& t);  // on a scan thread, mu_ held
  // Real time: pause the logic and wait until no task is inside a scan; a
  // note for the user when one stays in its scan.
  std::string pause_and_settle();
  // Writes for the global image are waiting in writes_: the next scan takes
  // the image lock (before mu_) to apply them.
  std::atomic<bool> image_writes_pending_{false};
  void apply_writes(TaskRuntime& t, const ScanContext& ctx, bool image_locked);

  // Real time: reads waiting for the end of a task's scan (mu_).
  static constexpr std::size_t kMaxScanReads = 32;
  struct ScanRead {
    const VarInfo* var = nullptr;
    bool done = false;
    alignas(8) unsigned char value[sizeof(STRING)];
  };
  std::array<ScanRead, kMaxScanReads> scan_reads_{};
  std::size_t scan_reads_n_ = 0;
  std::condition_variable reads_cv_;
  std::atomic<bool> stop_hit_{false};
  std::string stop_reason_;
  std::atomic<bool> interrupted_{false};
  std::atomic<bool> end_requested_{false};
  bool quit_ = false;
  bool in_freeze_ = false;
  std::string reloaded_;  // an online change was made in this session (reload.cpp)
  retain::Manager* retain_ = nullptr;
  // What the debugger holds that points into programs a reload replaces,
  // re-resolved against the new build; each task takes its part at its
  // switch point (after_latch, under mu_). reload.cpp.
  struct Carry;
  std::shared_ptr<Carry> carry_;
  std::shared_ptr<const VarRegistry> trace_vars_;  // the registry the trace resolved against
  void carry_over(const TaskRuntime& t);
  TaskRuntime* frozen_task_ = nullptr;  // the task whose scan a freeze point holds
  int freeze_action_ = 0;               // 0 continue, 1 step (pause at scan end), 2 quit
  Reader reader_;
  Writer writer_;
  std::string joined_line_;  // the command line being executed (conditions keep their spacing)
};

}  // namespace plc::debug

// The debugger's `reload [LIB]` command: online change of a cell library
// (plc/online_change.hpp) from the console.
//
// Each task switches at its own scan boundary. In virtual time, and in real
// time while the logic is paused, no task is inside a scan between two
// commands, so every task is at a boundary and the switch is made at once;
// in real time with the logic running, each task switches at its next scan
// and the command waits (bounded) until every task concerned has.
//
// What the debugger holds that points into the old programs is re-resolved
// afterwards by path: breakpoint conditions, forces and the trace's
// variable list (watches are kept by name). A recording being written
// notes the change at the latch where each task switches, and keeps a copy
// of the new build, so that its replay makes the same change at the same
// scan (plc/debug/recording.hpp). Refused while a trace file is being
// written (stop it first), during a replay (the replay makes the recorded
// changes itself), while frozen inside a scan, and in real time while the
// logic runs with conditions, forces or a trace set up (the task threads use
// those while the command would replace them).
//
// After a change, `goto` to an earlier scan is refused: it re-runs the
// session from the start, and the old build, gone from the library's path,
// could not run the scans before the change (a recording's replay can: it
// keeps the builds). `restart` runs the new build, as a real restart would.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <thread>

#include "plc/debug/debugger.hpp"
#include "plc/online_change.hpp"

namespace plc::debug {

std::string Debugger::cmd_reload(const std::vector<std::string>& a) {
  if (a.size() > 2) return "usage: reload [LIBRARY]\n";
  if (replayer_)
    return "reload: not during a replay (the replay makes the recorded online changes itself)\n";
  if (in_freeze_) return "reload: frozen inside a scan; step to the end of the scan first (step)\n";
  if (trace_ && trace_->running())
    return "reload: a trace file is being written; stop it first (trace stop)\n";
  const bool realtime_running = opt_.mode == io::ClockMode::RealTime && !rt_->paused();
  if (realtime_running) {
    const bool conditions =
        std::any_of(breaks_.begin(), breaks_.end(), [](const Breakpoint& b) { return b.cond; });
    if (conditions || !forces_.empty() || !trace_spec_.empty())
      return "reload: in real time with the logic running, remove conditional breakpoints, "
             "forces and the trace setup first, or pause\n";
  }
  const bool at_boundary = !realtime_running && rt_->wait_until_idle(std::chrono::seconds(1));
  std::string lib;
  if (a.size() == 2) lib = std::filesystem::absolute(a[1]).lexically_normal().string();

  OnlineChange change(*rt_);
  const ChangeReport report = change.prepare(lib);
  if (!report.refused.empty()) return report.text();
  if (recorder_) {
    // Before the commit: the tasks' next latches write the change records.
    if (std::string why = recorder_->note_change(change, report.text()); !why.empty())
      return "reload: " + why + "\n";
  }
  change.commit();
  if (at_boundary) {
    for (const auto& t : rt_->tasks())
      if (ProgramSwap* s = t->swap.load()) apply_program_swap(*t, *s);
  } else {
    // Bounded: ten periods of the slowest task, at least two seconds.
    TIME slowest{};
    for (const auto& t : rt_->tasks()) slowest = std::max(slowest, t->period);
    const auto limit = std::chrono::steady_clock::now() +
                       std::max<std::chrono::nanoseconds>(10 * slowest, std::chrono::seconds(2));
    while (!change.switched() && std::chrono::steady_clock::now() < limit)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!change.switched())
      return report.text() +
             "reload: not every task reached a scan boundary in time (a stopped or stuck "
             "task); the tasks that did run the new code, the others switch at their next "
             "scan\n";
  }
  change.finish();
  reloaded_ = "the library changed at scan " + std::to_string(scan_count());

  // Re-resolve what pointed into the old programs.
  std::string err;
  for (Breakpoint& b : breaks_)
    if (b.cond)
      b.cond =
          Condition::compile(b.cond->text(), rt_->vars(), rt_->image(), rt_->byte_order(), err);
  for (Force& f : forces_) {
    bool image = false;
    if (auto v = resolve(f.name, image, err)) f.var = *v;
  }
  writes_.clear();
  if (!trace_spec_.empty()) {
    auto spec = trace_spec_;
    trace_spec_.clear();
    trace_ = std::make_unique<Trace>(rt_->vars(), rt_->image(), rt_->byte_order());
    trace_->set_backpressure(opt_.mode == io::ClockMode::Virtual);
    if (opt_.mode == io::ClockMode::RealTime) {
      std::vector<std::string> names;
      for (const auto& t : rt_->tasks()) names.push_back(t->name);
      trace_->set_one_task(std::move(names));
    }
    for (const std::string& s : spec) execute("trace " + s);
  }
  {
    std::lock_guard<std::mutex> lock(mu_);
    note_scan_end_reads();
  }
  return report.text() + "switched: every task concerned runs the new build\n";
}

}  // namespace plc::debug

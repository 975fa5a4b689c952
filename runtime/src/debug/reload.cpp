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
// by path against the new build before the switch (Carry), and each task
// takes its part at its own switch point, in after_latch under mu_ (the
// lock the scan hooks use), so that no scan of the new code runs with a
// force, a condition or a trace of the old: breakpoint conditions, forces
// and the trace's variable list (watches are kept by name). A force on a
// variable the new build no longer has, or has with another type, is
// dropped and listed. A recording being written
// notes the change at the latch where each task switches, and keeps a copy
// of the new build, so that its replay makes the same change at the same
// scan (plc/debug/recording.hpp). Refused while a trace file is being
// written (stop it first), during a replay (the replay makes the recorded
// changes itself) and while frozen inside a scan.
//
// After a change, `goto` to an earlier scan is refused: it re-runs the
// session from the start, and the old build, gone from the library's path,
// could not run the scans before the change (a recording's replay can: it
// keeps the builds). `restart` runs the new build, as a real restart would.
#include <algorithm>
#include <chrono>
#include <thread>

#include "plc/config_path.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/online_change.hpp"
#include "plc/retain/retain_manager.hpp"

namespace plc::debug {

struct Debugger::Carry {
  struct Task {
    std::size_t order = 0;
    bool done = false;
  };
  const OnlineChange* change = nullptr;
  std::vector<Task> tasks;
  // Per force (index in forces_): its variable in the new build; nullopt:
  // dropped (gone, or another type).
  std::vector<std::optional<VarInfo>> forces;
  // Per breakpoint (index in breaks_) with a condition on a task's variables.
  std::vector<std::pair<std::size_t, std::optional<Condition>>> conds;
  // The new trace resolved against `vars`; declared after it, so destroyed
  // first (a replaced trace and its registry go the same way, swapped in).
  std::shared_ptr<const VarRegistry> vars;
  std::unique_ptr<Trace> trace;
  int trace_task = -1;
  std::vector<int> dead_breaks;  // ids of breakpoints whose condition is gone
};

// Under mu_: t's part of the change, once t runs the new build.
void Debugger::carry_over(const TaskRuntime& t) {
  Carry& c = *carry_;
  auto task = std::find_if(c.tasks.begin(), c.tasks.end(),
                           [&](const Carry::Task& x) { return x.order == t.order; });
  if (task == c.tasks.end() || task->done || !c.change->switched(t.order)) return;
  task->done = true;
  const int order = static_cast<int>(t.order);
  for (std::size_t i = 0; i < forces_.size() && i < c.forces.size(); ++i) {
    Force& f = forces_[i];
    if (f.image || f.var.task != order) continue;
    if (c.forces[i])
      f.var = *c.forces[i];
    else
      f.var.task = -2;  // dropped: no task applies it; removed when the change ends
  }
  for (auto& [i, cond] : c.conds)
    if (breaks_[i].task == order) {
      breaks_[i].cond = std::move(cond);
      cond.reset();
    }
  if (c.trace && c.trace_task == order) {
    trace_.swap(c.trace);
    std::swap(trace_vars_, c.vars);
  }
}

std::string Debugger::cmd_reload(const std::vector<std::string>& a) {
  if (a.size() > 2) return "usage: reload [LIBRARY]\n";
  if (replayer_)
    return "reload: not during a replay (the replay makes the recorded online changes itself)\n";
  if (in_freeze_) return "reload: frozen inside a scan; step to the end of the scan first (step)\n";
  if (trace_ && trace_->running())
    return "reload: a trace file is being written; stop it first (trace stop)\n";
  const bool realtime_running = opt_.mode == io::ClockMode::RealTime && !rt_->paused();
  const bool at_boundary = !realtime_running && rt_->wait_until_idle(std::chrono::seconds(1));
  std::string lib;
  if (a.size() == 2) {
    // From the current directory, as any path on a command line.
    std::string why;
    const auto abs = absolute_path(a[1], why);
    if (!abs) return "reload: " + why + "\n";
    lib = *abs;
  }

  OnlineChange change(*rt_);
  const ChangeReport report = change.prepare(lib);
  if (!report.refused.empty()) return report.text();
  // The retain file's next layout was built by prepare() (the manager
  // follows every change: retain::Manager::follow); it switches with the
  // last task.
  std::string retain_note;
  if (retain_) {
    retain_note =
        "  the retain file is saved in the new layout from the scan where the last task "
        "concerned switches\n";
  }

  // Re-resolve against the new build, before any task switches.
  auto carry = std::make_shared<Carry>();
  carry->change = &change;
  for (std::size_t t : change.tasks()) carry->tasks.push_back({t, false});
  carry->vars = std::make_shared<const VarRegistry>(change.next_vars());
  const VarRegistry& next = *carry->vars;
  std::string dropped;
  for (const Force& f : forces_) {
    std::optional<VarInfo> v;
    if (!f.image) {
      const VarInfo* n = next.find(f.name);
      if (n && n->type == f.var.type && !n->address)
        v = *n;
      else if (std::any_of(carry->tasks.begin(), carry->tasks.end(),
                           [&](const Carry::Task& t) { return int(t.order) == f.var.task; }))
        dropped += "  force on " + f.name +
                   " dropped: " + (n ? "its type changed" : "the new build has no such variable") +
                   "\n";
    }
    carry->forces.push_back(std::move(v));
  }
  std::string err;
  for (std::size_t i = 0; i < breaks_.size(); ++i)
    if (breaks_[i].cond) {
      auto cond = breaks_[i].cond->rebind(next, rt_->image(), rt_->byte_order(), err);
      if (!cond) {
        dropped += "  breakpoint " + std::to_string(breaks_[i].id) + " (" + breaks_[i].text +
                   ") deleted: its condition does not compile against the new build (" + err +
                   ")\n";
        carry->dead_breaks.push_back(breaks_[i].id);
      }
      carry->conds.emplace_back(i, std::move(cond));
    }
  if (!trace_spec_.empty()) {
    int fastest = 0;
    for (const auto& t : rt_->tasks())
      if (t->period == rt_->fastest_period()) {
        fastest = static_cast<int>(t->order);
        break;
      }
    carry->trace_task = trace_->sampling_task(fastest);
    carry->trace = make_trace(next);
  }
  if (recorder_) {
    // Before the commit: the tasks' next latches write the change records.
    if (std::string why = recorder_->note_change(change, report.text()); !why.empty())
      return "reload: " + why + "\n";
  }

  // Ends the change under mu_: every task that switched has its part, the
  // dropped forces go.
  auto settle = [&] {
    std::lock_guard<std::mutex> lock(mu_);
    change.withdraw();  // from here on no task switches any more
    for (const auto& t : rt_->tasks()) carry_over(*t);
    // Conditions of no one task (virtual time; the image only): now.
    if (change.switched())
      for (auto& [i, cond] : carry_->conds)
        if (breaks_[i].task < 0) breaks_[i].cond = std::move(cond);
    for (int id : carry_->dead_breaks)
      std::erase_if(breaks_, [&](const Breakpoint& b) { return b.id == id; });
    carry_.reset();
    std::erase_if(forces_, [](const Force& f) { return !f.image && f.var.task == -2; });
    writes_.clear();
    note_scan_end_reads();
  };
  {
    std::lock_guard<std::mutex> lock(mu_);
    carry_ = carry;
  }
  if (at_boundary) {
    change.switch_all_now();
  } else {
    change.commit();
    // Bounded: ten periods of the slowest task, at least two seconds.
    TIME slowest{};
    for (const auto& t : rt_->tasks()) slowest = std::max(slowest, t->period);
    const auto limit = std::chrono::steady_clock::now() +
                       std::max<std::chrono::nanoseconds>(10 * slowest, std::chrono::seconds(2));
    while (!change.switched() && std::chrono::steady_clock::now() < limit)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!change.switched()) {
      settle();
      // Partial: the tasks that switched keep the new build, and the
      // runtime keeps it alive for them (OnlineChange::finish).
      change.finish();
      if (change.partial())
        reloaded_ = "the library changed in part at scan " + std::to_string(scan_count());
      return report.text() + dropped +
             "reload: not every task reached a scan boundary in time (a stopped or stuck "
             "task); the tasks that did run the new code (until the cell stops), the others run "
             "the old code on" +
             (retain_ ? "; the retain file keeps the old layout (its values of the tasks that "
                        "switched stay as their last scan of the old code left them)"
                      : "") +
             "\n";
    }
  }
  settle();
  change.finish();
  reloaded_ = "the library changed at scan " + std::to_string(scan_count());
  return report.text() + retain_note + dropped +
         "switched: every task concerned runs the new build\n";
}

}  // namespace plc::debug

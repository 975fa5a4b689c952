// Online change: a new build of a cell library replaces the programs it
// provides while the cell runs, each task switching at its own scan
// boundary; other tasks, plugins and devices never stop.
//
//   OnlineChange oc(rt);
//   ChangeReport r = oc.prepare("/abs/path/build/libmycell.so");  // loads, compares
//   if (r.refused.empty()) { oc.commit(); ...scans run...; if (oc.switched()) oc.finish(); }
//
// prepare() loads the new build beside the old one (plc/cell_library.hpp),
// constructs the new programs and compares them field by field through the
// reflection (FieldVisitor), by path and type:
// - unchanged path and type: the value moves over, FB internal state
//   included (a running TON's start time, a counter, a batch's step);
// - new fields keep the initial value the new constructor gave them;
// - removed and type-changed fields are listed (the report comes before
//   the switch; their values are lost).
// RETAIN and PERSISTENT fields move over like every other field; the report
// lists separately the retained variables added, removed and retyped (what
// the retain file gains and loses). Refused, with the reason, old code
// running on: a program type missing from the new build, a constructor that
// throws, a located variable added, removed or moved to another address, a
// device port added or removed (the task layout and the devices come from
// the cell config, which an online change does not re-read), a library that
// registers device models or plugins (those run inside plugin threads), a
// task that is stopped, a load that fails (missing file, dlopen error, ABI
// version).
//
// commit() hands each task concerned its ProgramSwap; the task applies it
// at the start of its next scan (Runtime::scan_latch): the copies, then the
// new program pointers, in its own thread, so no scan ever sees half a
// change. Only fields in PLC_REFLECT move over: state a block keeps outside
// its reflection starts fresh. finish(), once switched() (every task has
// applied its swap, so none can be inside the old code), updates the
// variable registry, destroys the old programs and unloads the old library.
//
// What must change together with the programs, at one scan boundary (the
// retain file's layout, retain::Manager), follows the change as a
// SwitchFollower: the task that applies the last swap calls it, in its scan
// latch, before switched() can be true - so before finish() destroys the
// old programs. Whoever follows every change registers with the runtime
// (Runtime::add_change_observer): prepare() tells it, so no caller of
// prepare() can forget it.
//
// A change that not every task took (a task stuck or stopped before its
// switch point, a timeout: the caller withdraws it) is finished partially:
// the tasks that switched run the new build until the runtime goes (its
// programs and library are kept by the runtime, the registry shows them),
// the others run the old build on, and the old programs of the switched
// tasks are kept too (a follower that stayed with the old layout reads
// them). Nothing a task runs or a reader holds is destroyed before the
// runtime is.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "plc/program.hpp"
#include "plc/types.hpp"
#include "plc/var_registry.hpp"

namespace plc {

class Runtime;
class CellLibrary;
struct TaskRuntime;

struct ChangeReport {
  std::string library;
  std::vector<std::string> programs;  // "Main (MainProgram)"
  std::size_t kept = 0;               // fields whose value moves over
  std::vector<std::string> added;     // "Main.x: DINT"
  std::vector<std::string> removed;   // "Main.y: INT"
  std::vector<std::string> retyped;   // "Main.z: INT -> DINT"
  // The RETAIN/PERSISTENT variables of the replaced programs, old build
  // against new (a field that becomes retained counts as added, one that
  // no longer is as removed), as a restart reports the file's layout.
  std::size_t retain_kept = 0;
  std::vector<std::string> retain_added, retain_removed, retain_retyped;
  std::string refused;  // why not ("" = can be applied)
  [[nodiscard]] std::string text() const;
};

// See the header comment. on_switched() runs inside a scan (no allocation,
// no exceptions, no waiting beyond the image lock); on_dropped() on the
// thread that drops a change that did not switch every task (withdrawn, or
// never committed).
class SwitchFollower {
 public:
  virtual ~SwitchFollower() = default;
  virtual void on_switched() noexcept = 0;
  virtual void on_dropped() = 0;
};

// One task's part of a change, applied by the task's thread.
struct ProgramSwap {
  // Field values to move; runs of fields adjacent in both the old and the
  // new object are merged into one copy (a whole FB, usually). STRING is
  // assigned (its own copy), everything else copied bytewise.
  struct Copy {
    void* dst;
    const void* src;
    std::size_t bytes;
    bool string;
  };
  std::vector<std::pair<std::size_t, Program*>> programs;  // index in TaskRuntime::programs
  std::vector<Copy> copies;
  std::atomic<bool> applied{false};
  // Shared by the swaps of one change: how many are still to be applied, and
  // who follows the change (null: nobody). Set by OnlineChange::commit().
  struct Together {
    std::atomic<std::size_t> left{0};
    std::vector<SwitchFollower*> followers;
  };
  Together* together = nullptr;
};
// At a scan boundary of `t`, in its thread (Runtime::scan_latch).
void apply_program_swap(TaskRuntime& t, ProgramSwap& s);

class OnlineChange {
 public:
  explicit OnlineChange(Runtime& rt);
  ~OnlineChange();
  OnlineChange(const OnlineChange&) = delete;
  OnlineChange& operator=(const OnlineChange&) = delete;

  // `library`: a path the cell config's `libraries:` named (absolute, as
  // CellConfig holds it), or "" when the cell has exactly one. `file`, when
  // given, is where the new build's bytes come from (a replay's kept copy).
  ChangeReport prepare(const std::string& library, const std::string& file = "");
  // After prepare(), before commit(): `f` switches with the last task
  // (SwitchFollower). It must outlive this object. The runtime's change
  // observers (Runtime::add_change_observer: the retain manager) are told
  // by prepare() and call this themselves.
  void follow(SwitchFollower* f);
  // After prepare(): the new build, and the tasks (TaskRuntime::order) that
  // switch to it.
  [[nodiscard]] const std::shared_ptr<CellLibrary>& next_library() const { return new_lib_; }
  [[nodiscard]] std::vector<std::size_t> tasks() const;
  // Switches every task at once: only when no task is inside a scan
  // (virtual time, a paused cell, a cell not yet started).
  void switch_all_now();
  void commit();
  [[nodiscard]] bool switched() const;
  // Whether task `task` (TaskRuntime::order) runs the new build already.
  [[nodiscard]] bool switched(std::size_t task) const;
  // Takes the change back from the tasks that have not switched yet (they
  // run the old build on); after it, switched(task) no longer changes (a
  // task that took its swap just before is waited for: it is in runtime
  // code, a few copies from done).
  void withdraw();
  // After prepare(): the variable registry as finish() will make it (the
  // debugger re-resolves what it holds against it before the switch).
  [[nodiscard]] VarRegistry next_vars() const;
  // After switched(): the change is complete. After withdraw() with only
  // some tasks switched: the partial finish (see the top). Called by the
  // destructor when the owner did not.
  void finish();
  // Whether finish() found only some tasks switched.
  [[nodiscard]] bool partial() const { return partial_; }
  // Recording (plc/debug/recording.hpp) and other observers: the report of
  // the last finished change.
  [[nodiscard]] const ChangeReport& report() const { return report_; }

 private:
  struct Replaced {
    std::string name;
    int task = -1;
    std::unique_ptr<Program> next;
  };
  std::vector<VarInfo> program_vars(const Replaced& rp) const;

  Runtime& rt_;
  ChangeReport report_;
  std::shared_ptr<CellLibrary> old_lib_, new_lib_;
  std::vector<Replaced> replaced_;
  std::vector<std::pair<TaskRuntime*, std::unique_ptr<ProgramSwap>>> swaps_;
  ProgramSwap::Together together_;
  bool committed_ = false;
  bool finished_ = false;
  bool withdrawn_ = false;
  bool partial_ = false;
};

}  // namespace plc

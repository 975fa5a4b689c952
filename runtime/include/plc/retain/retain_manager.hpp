// Retain for one cell: restores RETAIN and PERSISTENT variables at start-up
// as the start mode says (IEC 61131-3 warm / cold start, or a reset), takes
// a snapshot at a scan boundary at most every `save_every`, and saves a last
// one at a controlled stop.
//
// Snapshots: every `save_every` of scan time a snapshot is due. Then each
// task, at the end of its next scan (after its changes are merged, before
// the outputs are published: ScanHooks::before_publish, under the image lock
// in real time), copies its retained variables (and the retained %M, from
// the global image) into the live buffer; so each task's values come from
// one whole scan of it, never a torn one. When every running task has done
// so, the buffer goes to the writer (Writer::offer: one memcpy, or a
// counted skip while the writer is busy). Other scans only compare a time.
//
// Online change (plc/online_change.hpp, the debugger's `reload`) of programs
// with retained fields - every change: the change itself tells the manager
// (Runtime::add_change_observer) - follow() builds the new build's layout
// (and its buffers) on the calling thread, outside the scans; the layout
// switches, by a pointer swap under the image lock, at the scan boundary
// where the last task concerned switches its programs (OnlineChange's
// SwitchFollower, before that task's first scan of the new code). The
// reading chosen for several tasks: until every task concerned has
// switched, snapshots are gathered in the old layout - a task that switched
// already contributes the values its last scan of the old code left in the
// old programs (alive until the change is finished, and no longer written) -
// so every snapshot is of one layout, each task's part from one whole scan
// of it (switched at the first task, a task whose scan was under way then
// would save its new programs' fields before its own switch gave them their
// values); a snapshot half gathered at the switch is dropped, and the next
// scan starts one in the new layout. A snapshot offered before the switch
// and written after it is written whole in its old layout (Writer::Slot).
// Each copy on disk is self-contained and a start restores by path and
// type, so a crash leaves the newest valid copy in one layout or the other,
// never a mix.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "plc/online_change.hpp"
#include "plc/retain/retain_layout.hpp"
#include "plc/retain/retain_storage.hpp"
#include "plc/retain/retain_writer.hpp"
#include "plc/runtime.hpp"

namespace plc::retain {

enum class StartMode {
  Auto,        // warm when a valid retain file exists, else cold
  Warm,        // RETAIN and PERSISTENT restored, everything else initial
  WarmOrCold,  // Auto, but a cold start also when every copy is damaged, whatever on_damage says
  Cold,        // PERSISTENT restored, RETAIN and everything else initial
  Reset,       // the retain file removed, everything initial
};

// What a start does when copies of the retain file exist but none is
// valid: start with initial values (loudly), or not at all.
enum class OnDamage { Cold, Stop };
// --warm-or-cold goes cold whatever the config says; otherwise the config's
// `on_damage:` decides; unset, an explicit warm start (--warm) stops - the
// operator asked for the retained values, a cold start would silently drop
// them - and every other start goes cold.
OnDamage on_damage_policy(StartMode requested, RetainOnDamage configured);

struct StartReport {
  StartMode requested = StartMode::Auto;
  StartMode mode = StartMode::Cold;  // what was done (Auto resolved; refused: as requested)
  bool loaded = false;               // a valid copy was read
  bool refused = false;              // every copy damaged and the policy says stop
  std::string from;                  // its file
  std::uint64_t sequence = 0;
  std::size_t restored = 0, initial = 0;  // retained entries restored / left initial
  std::vector<std::string> added, removed, type_changed;  // layout differences
  std::vector<std::string> problems;                      // damaged copies, errors
  // Copies existed but none was valid, and the cell started anyway with
  // initial values (what the summary and the HMI point out).
  [[nodiscard]] bool fell_back() const;
  // The lines plcrun prints at the start; headline() is the one that says
  // what kind of start it was (the summary repeats it).
  [[nodiscard]] std::vector<std::string> lines() const;
  [[nodiscard]] std::string headline() const;
};

class Manager : public ScanHooks, public SwitchFollower, public ChangeObserver {
 public:
  Manager(Runtime& rt, const RetainConfig& cfg);
  ~Manager() override;
  Manager(const Manager&) = delete;
  Manager& operator=(const Manager&) = delete;

  // Before the first scan: restores per `mode`, starts the writer and hooks
  // into the scans. When every copy is damaged and the policy
  // (on_damage_policy) says stop, nothing is restored or started and the
  // report says `refused`: the caller must not run the cell (the damaged
  // copies stay as they are, for whoever repairs them).
  StartReport start(StartMode mode);
  // After the last scan (Runtime::finish): the last snapshot, written on
  // this thread. "" or the error.
  std::string stop();

  // Online change (ChangeObserver): from start() to stop() the manager is
  // registered with the runtime, and OnlineChange::prepare() calls this
  // for every change, once it can be applied and before it is committed:
  // it builds the layout of the registry the change will leave
  // (OnlineChange::next_vars) and follows the change (see the top).
  void follow(OnlineChange& change) override;

  // The layout the scans save in now (not while tasks run: it may switch).
  [[nodiscard]] const Layout& layout() const { return cur_->layout; }
  [[nodiscard]] WriterStats stats() const { return writer_.stats(); }
  Writer& writer() { return writer_; }
  Storage& storage() { return storage_; }

  void before_publish(TaskRuntime& t, io::ProcessImage& global) override;
  // The scans may copy and merge only their bound bytes: the manager writes
  // no image byte during the scans (restores happen before the first), and
  // reads only the global image, after the task's merge (located retained
  // variables and retained %M ranges point there, retain_layout.cpp), never
  // a task's private copy. A byte no program is bound to changes in the
  // global image only by a write from outside (debugger, HMI, the restore),
  // so it holds the same value whether the scans copy it or not.
  [[nodiscard]] bool whole_image() const override { return false; }
  // SwitchFollower: the last task concerned switched its programs (its
  // thread, inside its scan latch) / the change was dropped.
  void on_switched() noexcept override;
  void on_dropped() override;

 private:
  // One layout with its buffers: the live snapshot the tasks copy into and
  // the slot it is handed to the writer through.
  struct Generation {
    Generation(const VarRegistry& vars, const RetainConfig& cfg, io::ProcessImage& image)
        : layout(vars, cfg, image), live(layout.bytes()), slot(layout) {}
    Layout layout;
    std::vector<std::uint8_t> live;
    Writer::Slot slot;
  };
  // Frees the generations neither the scans nor the writer can still use.
  void retire_generations();

  Runtime& rt_;
  RetainConfig cfg_;
  TIME save_every_;
  Storage storage_;
  Writer writer_;
  std::vector<std::unique_ptr<Generation>> gens_;  // owned; cur_, next_ point into it
  // The scans' layout, and the one an online change switches to. Both are
  // changed under the image lock (real time), as before_publish runs.
  Generation* cur_ = nullptr;
  Generation* next_ = nullptr;
  TIME next_due_{};
  bool started_ = false;
  // The snapshot being gathered: which tasks copied their part into live.
  bool gathering_ = false;
  std::vector<bool> captured_;
};

}  // namespace plc::retain

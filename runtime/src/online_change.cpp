#include "plc/online_change.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <thread>

#include "plc/cell_library.hpp"
#include "plc/runtime.hpp"

namespace plc {
namespace {

std::string type_text(VarType t) { return std::string(to_string(t)); }

// Merges copies whose fields lie back to back in both objects (no gap:
// a gap may hold a member outside the reflection, which must not move).
std::vector<ProgramSwap::Copy> merged(std::vector<ProgramSwap::Copy> c) {
  std::sort(c.begin(), c.end(),
            [](const auto& a, const auto& b) { return std::less<const void*>()(a.dst, b.dst); });
  std::vector<ProgramSwap::Copy> out;
  for (const auto& x : c) {
    if (!out.empty() && !x.string && !out.back().string &&
        static_cast<char*>(out.back().dst) + out.back().bytes == x.dst &&
        static_cast<const char*>(out.back().src) + out.back().bytes == x.src)
      out.back().bytes += x.bytes;
    else
      out.push_back(x);
  }
  return out;
}

std::string same_path(const std::string& a) {
  return std::filesystem::path(a).lexically_normal().string();
}

}  // namespace

std::string ChangeReport::text() const {
  std::string s;
  if (!refused.empty()) return "online change refused: " + refused + "; the old code runs on\n";
  s += "online change of " + library + ":\n";
  for (const auto& p : programs) s += "  program " + p + "\n";
  s += "  " + std::to_string(kept) + " fields keep their values\n";
  for (const auto& a : added) s += "  added (initial value): " + a + "\n";
  for (const auto& r : removed) s += "  removed (value dropped): " + r + "\n";
  for (const auto& r : retyped) s += "  type changed (initial value): " + r + "\n";
  if (retain_kept || !retain_added.empty() || !retain_removed.empty() || !retain_retyped.empty())
    s += "  retained (RETAIN/PERSISTENT): " + std::to_string(retain_kept) +
         " keep their values and their place in the retain file\n";
  for (const auto& a : retain_added) s += "  retained, new in the retain file: " + a + "\n";
  for (const auto& r : retain_retyped)
    s += "  retained, type changed in the retain file: " + r + "\n";
  for (const auto& r : retain_removed)
    s += "  retained no more (dropped from the retain file): " + r + "\n";
  return s;
}

void apply_program_swap(TaskRuntime& t, ProgramSwap& s) {
  // No allocation: STRING is a fixed-capacity value type.
  for (const ProgramSwap::Copy& c : s.copies) {
    if (c.string)
      *static_cast<STRING*>(c.dst) = *static_cast<const STRING*>(c.src);
    else
      std::memcpy(c.dst, c.src, c.bytes);
  }
  for (const auto& [index, p] : s.programs) t.programs[index] = p;
  t.swap.store(nullptr, std::memory_order_relaxed);
  // The last task to switch switches the followers, before any applied
  // flag can make switched() true.
  if (s.together && s.together->left.fetch_sub(1, std::memory_order_acq_rel) == 1)
    for (SwitchFollower* f : s.together->followers) f->on_switched();
  s.applied.store(true, std::memory_order_release);
}

OnlineChange::OnlineChange(Runtime& rt) : rt_(rt) {}

OnlineChange::~OnlineChange() {
  // A change handed to the tasks is seen through: a task that applied its
  // swap runs the new programs, which must then live as long as the
  // runtime (finish(), partially if not every task switched). One that was
  // only prepared is dropped here, with the new library.
  if (committed_ && !finished_) {
    withdraw();
    finish();
  }
  if (!finished_)
    for (SwitchFollower* f : together_.followers) f->on_dropped();
}

void OnlineChange::follow(SwitchFollower* f) {
  if (std::find(together_.followers.begin(), together_.followers.end(), f) ==
      together_.followers.end())
    together_.followers.push_back(f);
}

ChangeReport OnlineChange::prepare(const std::string& library, const std::string& file) {
  ChangeReport r;
  auto refuse = [&](std::string why) {
    r.refused = std::move(why);
    // The new library stays loaded until this object goes: the programs
    // constructed from it (locals of prepare()) are destroyed after this.
    replaced_.clear();
    swaps_.clear();
    return r;
  };
  if (committed_) return refuse("a change is already under way");
  // Which of the cell's libraries.
  if (rt_.libraries_.empty()) return refuse("the cell loads no libraries (key 'libraries:')");
  std::string names;
  for (const auto& l : rt_.libraries_) {
    names += (names.empty() ? "" : ", ") + l->path();
    if ((library.empty() && rt_.libraries_.size() == 1) ||
        same_path(l->path()) == same_path(library))
      old_lib_ = l;
  }
  if (!old_lib_)
    return refuse(library.empty()
                      ? "the cell loads several libraries (" + names + "): name one"
                      : library + " is not one of the cell's libraries (" + names + ")");
  r.library = old_lib_->path();
  try {
    new_lib_ = CellLibrary::open(old_lib_->path(), file);
  } catch (const CellLibraryError& e) {
    return refuse("cannot load " + old_lib_->path() + ": " + e.what());
  }
  if (!old_lib_->models().empty() || !old_lib_->plugins().empty() || !new_lib_->models().empty() ||
      !new_lib_->plugins().empty())
    return refuse(
        "the library registers device models or plugins, which run in plugin threads: "
        "online change replaces programs only (restart the cell)");
  for (const auto& [type, _] : old_lib_->programs())
    if (!new_lib_->programs().count(type))
      return refuse("program type '" + type + "' is no longer in the library (restart the cell)");

  std::map<TaskRuntime*, std::unique_ptr<ProgramSwap>> swaps;
  for (const auto& [name, type] : rt_.program_types_) {
    if (!old_lib_->programs().count(type)) continue;
    TaskRuntime* task = nullptr;
    for (const auto& t : rt_.tasks_)
      if (std::find(t->program_names.begin(), t->program_names.end(), name) !=
          t->program_names.end())
        task = t.get();
    if (!task) continue;
    if (task->stopped.load())
      return refuse("task '" + task->name + "' (program '" + name +
                    "') is stopped: it would never reach a scan boundary to switch at");
    Program* old = rt_.program(name);
    std::unique_ptr<Program> next;
    try {
      next = new_lib_->programs().at(type)();
    } catch (const std::exception& e) {
      return refuse("program '" + name + "': the constructor of " + type + " threw: " + e.what());
    } catch (...) {
      return refuse("program '" + name + "': the constructor of " + type + " threw");
    }
    // init() as at a start (Program::init), on the new object alone: its
    // located variables and ports are not bound yet (they write a scratch
    // value), and the values that carry over are copied over it at the
    // switch - so it initialises what is new (CODESYS calls FB_init with
    // bInCopyCode = TRUE on an online change, then copies).
    try {
      next->init();
    } catch (const std::exception& e) {
      return refuse("program '" + name + "': init() of " + type + " threw: " + e.what());
    } catch (...) {
      return refuse("program '" + name + "': init() of " + type + " threw");
    }
    FieldVisitor before(name), after(name);
    old->describe(before);
    next->describe(after);
    const auto& binds = rt_.program_binds_[name];

    // Located variables and device ports: the I/O layout must not move.
    for (auto& l : after.located) {
      if (auto b = binds.find(l.path); b != binds.end()) l.var->set_address(b->second);
      auto o = std::find_if(before.located.begin(), before.located.end(),
                            [&](const auto& x) { return x.path == l.path; });
      if (o == before.located.end())
        return refuse("located variable " + l.path + " (" + std::string(l.var->address()) +
                      ") is new: the I/O layout cannot change online (restart the cell)");
      if (o->var->address() != l.var->address() || o->type != l.type)
        return refuse("located variable " + l.path + " moved from " +
                      std::string(o->var->address()) + " " + type_text(o->type) + " to " +
                      std::string(l.var->address()) + " " + type_text(l.type) +
                      ": the I/O layout cannot change online (restart the cell)");
    }
    for (const auto& o : before.located)
      if (std::none_of(after.located.begin(), after.located.end(),
                       [&](const auto& x) { return x.path == o.path; }))
        return refuse("located variable " + o.path + " (" + std::string(o.var->address()) +
                      ") was removed: the I/O layout cannot change online (restart the cell)");
    for (auto& p : after.ports) {
      if (auto b = binds.find(p.path); b != binds.end()) p.port->set_device_name(b->second);
      auto o = std::find_if(before.ports.begin(), before.ports.end(),
                            [&](const auto& x) { return x.path == p.path; });
      if (o == before.ports.end() || o->port->device_name() != p.port->device_name())
        return refuse("device port " + p.path +
                      " is new or names another device: devices "
                      "cannot be added or removed online (restart the cell)");
    }
    if (before.ports.size() != after.ports.size())
      return refuse("a device port of program '" + name +
                    "' was removed: devices cannot be added or removed online (restart the cell)");
    // Retained variables, old build against new: what the retain file's
    // layout gains and loses (their values follow the rules above).
    std::map<std::string, VarType> old_retained;
    for (const auto& f : before.fields)
      if (f.retain != RetainClass::None) old_retained[f.path] = f.type;
    for (const auto& l : before.located)
      if (l.retain != RetainClass::None) old_retained[l.path] = l.type;
    auto retained_now = [&](const std::string& path, VarType type) {
      auto o = old_retained.find(path);
      if (o == old_retained.end()) {
        r.retain_added.push_back(path + ": " + type_text(type));
        return;
      }
      if (o->second != type)
        r.retain_retyped.push_back(path + ": " + type_text(o->second) + " -> " + type_text(type));
      else
        ++r.retain_kept;
      old_retained.erase(o);
    };
    for (const auto& f : after.fields)
      if (f.retain != RetainClass::None) retained_now(f.path, f.type);
    for (const auto& l : after.located)
      if (l.retain != RetainClass::None) retained_now(l.path, l.type);
    for (const auto& f : before.fields)
      if (old_retained.count(f.path)) r.retain_removed.push_back(f.path + ": " + type_text(f.type));
    for (const auto& l : before.located)
      if (old_retained.count(l.path)) r.retain_removed.push_back(l.path + ": " + type_text(l.type));

    // Bind the new program where the old one is bound.
    for (auto& l : after.located) {
      const VarInfo* v = rt_.vars().find(l.path);
      l.var->bind(v->image_ptr, v->address->bit, rt_.order_);
    }
    for (auto& p : after.ports) {
      for (auto& d : rt_.devices_)
        if (d.name == p.port->device_name()) {
          auto in = task->image.area(io::Area::Input).subspan(d.in.byte, d.sizes.input_bytes);
          auto out = task->image.area(io::Area::Output).subspan(d.out.byte, d.sizes.output_bytes);
          p.port->bind(in, out, &d.plugin->link(d.index));
        }
    }

    // Values by path and type.
    auto& swap = swaps[task];
    if (!swap) swap = std::make_unique<ProgramSwap>();
    std::map<std::string, const FieldVisitor::Field*> old_fields;
    for (const auto& f : before.fields) old_fields[f.path] = &f;
    for (const auto& f : after.fields) {
      auto o = old_fields.find(f.path);
      if (o == old_fields.end()) {
        r.added.push_back(f.path + ": " + type_text(f.type));
      } else if (o->second->type != f.type) {
        r.retyped.push_back(f.path + ": " + type_text(o->second->type) + " -> " +
                            type_text(f.type));
        old_fields.erase(o);
      } else {
        swap->copies.push_back({f.ptr, o->second->ptr, size_of(f.type), f.type == VarType::STRING});
        ++r.kept;
        old_fields.erase(o);
      }
    }
    for (const auto& f : before.fields)
      if (old_fields.count(f.path)) r.removed.push_back(f.path + ": " + type_text(f.type));
    for (std::size_t i = 0; i < task->programs.size(); ++i)
      if (task->programs[i] == old) swap->programs.emplace_back(i, next.get());
    r.programs.push_back(name + " (" + type + ")");
    replaced_.push_back({name, static_cast<int>(task->order), std::move(next)});
  }
  if (replaced_.empty())
    return refuse("no program of the cell uses a type from " + old_lib_->path());
  for (auto& [t, s] : swaps) {
    s->copies = merged(std::move(s->copies));
    swaps_.emplace_back(t, std::move(s));
  }
  // Whoever follows every change of this runtime (the retain manager)
  // follows this one, before anything can switch.
  for (ChangeObserver* o : rt_.change_observers_) {
    try {
      o->follow(*this);
    } catch (const std::exception& e) {
      return refuse(std::string("cannot follow the change: ") + e.what());
    }
  }
  report_ = r;
  return r;
}

std::vector<std::size_t> OnlineChange::tasks() const {
  std::vector<std::size_t> out;
  for (const auto& [t, _] : swaps_) out.push_back(t->order);
  return out;
}

void OnlineChange::switch_all_now() {
  commit();
  for (auto& [t, s] : swaps_)
    if (t->swap.load() == s.get()) apply_program_swap(*t, *s);
}

void OnlineChange::commit() {
  if (committed_ || swaps_.empty()) return;
  committed_ = true;
  together_.left.store(swaps_.size(), std::memory_order_relaxed);
  for (auto& [t, s] : swaps_) {
    s->together = &together_;
    t->swap.store(s.get(), std::memory_order_release);
  }
}

bool OnlineChange::switched() const {
  if (!committed_) return false;
  return std::all_of(swaps_.begin(), swaps_.end(), [](const auto& ts) {
    return ts.second->applied.load(std::memory_order_acquire);
  });
}

bool OnlineChange::switched(std::size_t task) const {
  return std::any_of(swaps_.begin(), swaps_.end(), [&](const auto& ts) {
    return ts.first->order == task && ts.second->applied.load(std::memory_order_acquire);
  });
}

void OnlineChange::withdraw() {
  // Once: a second call (the destructor's, after the owner's) would find a
  // swap it took back like one a task took, and wait for it forever. A
  // change not committed was never handed to a task.
  if (withdrawn_ || !committed_) return;
  for (auto& [t, s] : swaps_) {
    ProgramSwap* expect = s.get();
    if (t->swap.compare_exchange_strong(expect, nullptr) || expect != nullptr) continue;
    // The task took the swap and is applying it (apply_program_swap: the
    // copies, then `applied`); runtime code that always completes.
    while (!s->applied.load(std::memory_order_acquire)) std::this_thread::yield();
  }
  withdrawn_ = true;
}

VarRegistry OnlineChange::next_vars() const {
  VarRegistry next = rt_.vars_;
  for (const Replaced& rp : replaced_) next.replace_prefix(rp.name + ".", program_vars(rp));
  return next;
}

// The registry entries of a replaced program, built from the new object.
std::vector<VarInfo> OnlineChange::program_vars(const Replaced& rp) const {
  FieldVisitor fv(rp.name);
  rp.next->describe(fv);
  std::vector<std::pair<std::size_t, VarInfo>> vars;
  for (const auto& f : fv.fields) vars.emplace_back(f.seq, plain_var_info(f, rp.task));
  for (const auto& l : fv.located) {
    VarInfo v = *rt_.vars().find(l.path);  // same address (prepare() checked)
    v.read_only = l.access.read_only;
    v.check = l.access.check;
    vars.emplace_back(l.seq, std::move(v));
  }
  std::sort(vars.begin(), vars.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<VarInfo> list;
  for (auto& [_, v] : vars) list.push_back(std::move(v));
  return list;
}

void OnlineChange::finish() {
  if (finished_ || !committed_) return;
  const bool complete = switched();
  // Partial: only once no task can switch any more.
  if (!complete && !withdrawn_) return;
  finished_ = true;
  std::vector<std::unique_ptr<Program>> retired;
  for (Replaced& rp : replaced_) {
    // Not switched (partial change): its task runs the old program on.
    if (!complete && !switched(static_cast<std::size_t>(rp.task))) continue;
    rt_.vars_.replace_prefix(rp.name + ".", program_vars(rp));
    for (auto& [n, p] : rt_.programs_)
      if (n == rp.name) {
        retired.push_back(std::move(p));
        p = std::move(rp.next);
      }
  }
  if (!complete) {
    // The switched tasks run the new programs (now the runtime's) from the
    // new library until the runtime goes; the old programs they left stay
    // for whoever kept the old layout (the followers are dropped: they
    // never saw the last task switch). The new programs of the other tasks
    // never ran: they go, with the library if no task switched at all.
    partial_ = !retired.empty();
    if (partial_) rt_.partial_libraries_.push_back(new_lib_);
    for (auto& p : retired) rt_.retired_programs_.push_back(std::move(p));
    replaced_.clear();
    old_lib_.reset();
    new_lib_.reset();
    for (SwitchFollower* f : together_.followers) f->on_dropped();
    return;
  }
  // No task can be inside the old code any more (each has started a scan
  // with the new programs): destroy the old programs, then let the old
  // library go (unloaded when the last holder drops it). The old programs an
  // earlier partial change kept go too: their code is in that library, and
  // no follower reads them once every task has switched (the retain layout
  // switched with the last task).
  for (auto& p : rt_.retired_programs_) retired.push_back(std::move(p));
  rt_.retired_programs_.clear();
  retired.clear();
  for (auto& l : rt_.libraries_)
    if (l == old_lib_) l = new_lib_;
  make_current(new_lib_);
  old_lib_.reset();
  new_lib_.reset();
}

}  // namespace plc

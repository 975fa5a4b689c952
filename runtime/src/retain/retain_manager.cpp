#include "plc/retain/retain_manager.hpp"

#include <algorithm>
#include <unordered_map>

namespace plc::retain {
namespace {

const char* mode_name(StartMode m) {
  switch (m) {
    case StartMode::Warm:
      return "warm start";
    case StartMode::Cold:
      return "cold start";
    case StartMode::Reset:
      return "reset";
    case StartMode::Auto:
    case StartMode::WarmOrCold:
      break;
  }
  return "start";
}

std::string type_name(std::uint8_t t) {
  if (t == kMemoryBytes) return "bytes";
  if (t > static_cast<std::uint8_t>(VarType::STRING)) return "type " + std::to_string(t);
  return to_string(static_cast<VarType>(t));
}

std::string listed(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

}  // namespace

OnDamage on_damage_policy(StartMode requested, RetainOnDamage configured) {
  if (requested == StartMode::WarmOrCold) return OnDamage::Cold;
  if (configured == RetainOnDamage::Cold) return OnDamage::Cold;
  if (configured == RetainOnDamage::Stop) return OnDamage::Stop;
  return requested == StartMode::Warm ? OnDamage::Stop : OnDamage::Cold;
}

bool StartReport::fell_back() const {
  return !loaded && !refused && mode != StartMode::Reset && !problems.empty();
}

std::string StartReport::headline() const {
  const std::string head = mode_name(mode);
  if (mode == StartMode::Reset)
    return head + ": retain file removed; every variable at its initial value";
  if (refused)
    return head +
           " REFUSED: no valid copy of the retain file (all damaged); the cell does not start "
           "(plcrun --warm-or-cold, or on_damage: cold in the retain: section, starts it with "
           "every variable at its initial value)";
  if (fell_back())
    return requested == StartMode::Cold
               ? head +
                     ": no valid copy of the retain file (all damaged), PERSISTENT values lost "
                     "too; every variable at its initial value"
               : head +
                     " INSTEAD OF A WARM START: no valid copy of the retain file (all "
                     "damaged); every variable at its initial value";
  if (!loaded) return head + ": no retain file yet; every variable at its initial value";
  return head + " from " + from + " (sequence " + std::to_string(sequence) +
         "): " + std::to_string(restored) + " restored, " + std::to_string(initial) +
         " at initial values" +
         (mode == StartMode::Cold ? " (RETAIN: a cold start keeps only PERSISTENT)" : "");
}

std::vector<std::string> StartReport::lines() const {
  std::vector<std::string> out;
  for (const auto& p : problems) out.push_back("damaged copy " + p);
  out.push_back(headline());
  if (!loaded) return out;
  if (!added.empty()) out.push_back("not in the file (initial values): " + listed(added));
  if (!type_changed.empty())
    out.push_back("type changed (initial values): " + listed(type_changed));
  if (!removed.empty())
    out.push_back("in the file but no longer declared (dropped): " + listed(removed));
  return out;
}

Manager::Manager(Runtime& rt, const RetainConfig& cfg)
    : rt_(rt),
      cfg_(cfg),
      save_every_(cfg.save_every.value),
      storage_(cfg.path),
      writer_(storage_),
      captured_(rt.tasks().size(), false) {
  gens_.push_back(std::make_unique<Generation>(rt.vars(), cfg_, rt.image()));
  cur_ = gens_.back().get();
}

Manager::~Manager() {
  if (!started_) return;
  rt_.remove_hooks(this);
  rt_.remove_change_observer(this);
}

StartReport Manager::start(StartMode mode) {
  StartReport r;
  r.requested = mode;
  Storage::Loaded l = storage_.load();
  r.problems = l.problems;
  if (mode != StartMode::Reset && !l.image && !l.problems.empty() &&
      on_damage_policy(mode, cfg_.on_damage.value) == OnDamage::Stop) {
    r.refused = true;
    r.mode = mode;  // nothing was done
    return r;
  }
  // A warm start without a valid copy is a cold start, and says so.
  if (mode == StartMode::Auto || mode == StartMode::WarmOrCold || mode == StartMode::Warm)
    mode = l.image ? StartMode::Warm : StartMode::Cold;
  r.mode = mode;
  std::uint64_t next = 1;
  if (mode == StartMode::Reset) {
    const std::string err = storage_.discard();
    if (!err.empty()) r.problems.push_back(err);
    l.image.reset();
  }
  if (l.image) {
    r.loaded = true;
    r.from = l.from;
    r.sequence = l.image->sequence;
    next = l.image->sequence + 1;
    std::unordered_map<std::string_view, const FileEntry*> in_file;
    for (const FileEntry& f : l.image->entries) in_file.emplace(f.path, &f);
    for (const Entry& e : cur_->layout.entries()) {
      auto it = in_file.find(e.path);
      if (it == in_file.end()) {
        r.added.push_back(e.path);
        ++r.initial;
        continue;
      }
      const FileEntry& f = *it->second;
      in_file.erase(it);
      if (f.type != e.type || f.value.size() != e.size) {
        r.type_changed.push_back(e.path + " (" + type_name(f.type) + " -> " + type_name(e.type) +
                                 ")");
        ++r.initial;
      } else if (mode == StartMode::Warm || e.cls == RetainClass::Persistent) {
        cur_->layout.restore(e, f.value.data());
        ++r.restored;
      } else {
        ++r.initial;
      }
    }
    for (const FileEntry& f : l.image->entries)
      if (in_file.count(f.path)) r.removed.push_back(f.path);
    // The tasks' private copies show the restored %M before the first scan.
    for (const auto& t : rt_.tasks()) t->image.copy_from(rt_.image());
  } else {
    r.initial = cur_->layout.entries().size();
  }
  // Every task's part as the start-up leaves it (a task that stops before
  // its first capture is saved with these values).
  cur_->layout.capture(-1, true, cur_->live);
  writer_.start(next);
  rt_.add_hooks(this);
  rt_.add_change_observer(this);  // every online change from now on: follow()
  started_ = true;
  next_due_ = rt_.now();
  return r;
}

void Manager::before_publish(TaskRuntime& t, io::ProcessImage&) {
  Generation& g = *cur_;
  if (!gathering_) {
    if (t.scan_time < next_due_) return;
    // A save is complete one file write after its snapshot: take the next
    // snapshot that much before the period ends, so that the newest complete
    // copy is never older than save_every (plus a scan) while writes take
    // about as long as the recent ones. Never more often than every half
    // period.
    next_due_ = t.scan_time + std::max<TIME>(save_every_ / 2, save_every_ - writer_.write_lead());
    gathering_ = true;
    std::fill(captured_.begin(), captured_.end(), false);
  }
  if (captured_[t.order]) return;
  g.layout.capture(static_cast<int>(t.order), true, g.live);
  captured_[t.order] = true;
  // A stopped task scans no more: its part stays as its last scan left it.
  for (const auto& other : rt_.tasks())
    if (!captured_[other->order] && !other->stopped.load(std::memory_order_relaxed)) return;
  gathering_ = false;
  // The writer still busy with the previous save (a slow disk): try again
  // at the next scan rather than a period later.
  if (!writer_.offer(g.slot, g.live)) next_due_ = t.scan_time;
}

void Manager::follow(OnlineChange& change) {
  retire_generations();
  // Allocation here, on the caller's thread: the switch is a pointer swap.
  auto g = std::make_unique<Generation>(change.next_vars(), cfg_, rt_.image());
  Generation* next = g.get();
  gens_.push_back(std::move(g));
  rt_.with_image_locked([&] { next_ = next; });
  change.follow(this);
}

void Manager::on_switched() noexcept {
  rt_.with_image_locked([this] {
    if (!next_) return;
    cur_ = next_;
    next_ = nullptr;
    // A snapshot half gathered in the old layout is dropped; the next scan
    // of any task starts one in the new layout, so the file changes layout
    // at once. A stopped task never captures again: its part now (its
    // values are those its last scan left; it runs nothing).
    gathering_ = false;
    next_due_ = TIME::min();
    for (const auto& t : rt_.tasks())
      if (t->stopped.load(std::memory_order_relaxed))
        cur_->layout.capture(static_cast<int>(t->order), false, cur_->live);
  });
}

void Manager::on_dropped() {
  rt_.with_image_locked([this] { next_ = nullptr; });
  retire_generations();
}

void Manager::retire_generations() {
  Generation *cur = nullptr, *next = nullptr;
  rt_.with_image_locked([&] {
    cur = cur_;
    next = next_;
  });
  // No scan offers an old slot after the switch; once the writer is done
  // with it (holds() false) nothing can touch it again.
  std::erase_if(gens_, [&](const std::unique_ptr<Generation>& g) {
    return g.get() != cur && g.get() != next && !writer_.holds(g->slot);
  });
}

std::string Manager::stop() {
  if (!started_) return {};
  rt_.remove_hooks(this);
  rt_.remove_change_observer(this);
  started_ = false;
  // No task runs any more: every value is where its last scan left it.
  cur_->layout.capture(-1, true, cur_->live);
  return writer_.stop(cur_->layout, cur_->live);
}

}  // namespace plc::retain

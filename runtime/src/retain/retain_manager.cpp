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
      on_damage_(cfg.on_damage.value),
      save_every_(cfg.save_every.value),
      layout_(rt.vars(), cfg, rt.image()),
      storage_(cfg.path),
      writer_(layout_, storage_),
      live_(layout_.bytes()),
      captured_(rt.tasks().size(), false) {}

Manager::~Manager() {
  if (started_) rt_.remove_hooks(this);
}

StartReport Manager::start(StartMode mode) {
  StartReport r;
  r.requested = mode;
  Storage::Loaded l = storage_.load();
  r.problems = l.problems;
  if (mode != StartMode::Reset && !l.image && !l.problems.empty() &&
      on_damage_policy(mode, on_damage_) == OnDamage::Stop) {
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
    for (const Entry& e : layout_.entries()) {
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
        layout_.restore(e, f.value.data());
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
    r.initial = layout_.entries().size();
  }
  // Every task's part as the start-up leaves it (a task that stops before
  // its first capture is saved with these values).
  layout_.capture(-1, true, live_);
  writer_.start(next);
  rt_.add_hooks(this);
  started_ = true;
  next_due_ = rt_.now();
  return r;
}

void Manager::before_publish(TaskRuntime& t, io::ProcessImage&) {
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
  layout_.capture(static_cast<int>(t.order), true, live_);
  captured_[t.order] = true;
  // A stopped task scans no more: its part stays as its last scan left it.
  for (const auto& other : rt_.tasks())
    if (!captured_[other->order] && !other->stopped.load(std::memory_order_relaxed)) return;
  gathering_ = false;
  // The writer still busy with the previous save (a slow disk): try again
  // at the next scan rather than a period later.
  if (!writer_.offer(live_)) next_due_ = t.scan_time;
}

std::string Manager::stop() {
  if (!started_) return {};
  rt_.remove_hooks(this);
  started_ = false;
  // No task runs any more: every value is where its last scan left it.
  layout_.capture(-1, true, live_);
  return writer_.stop(live_);
}

}  // namespace plc::retain

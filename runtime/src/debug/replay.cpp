// The replayer: runs a recording's records in file order against the cell
// without its devices (format and guarantees: recording.hpp).
#include <algorithm>
#include <cstring>
#include <new>

#include "plc/cell_library.hpp"
#include "plc/debug/recording.hpp"
#include "plc/online_change.hpp"

namespace plc::debug {

using namespace recfmt;

Replayer::Replayer(Runtime& rt, const std::string& file) : rt_(rt) {
  reader_ = std::make_unique<RecordingReader>(file);
  if (!(reader_->layout() == RecordingLayout::of(rt)))
    throw RecordingError("'" + file +
                         "' was recorded on a different cell layout (tasks, programs, devices or "
                         "image sizes differ)");
  {
    // The whole file first: a damaged recording, or one whose library
    // builds are not at hand, is refused before a scan.
    RecordingReader check(file);
    Record r;
    while (check.next(r)) {
      if (r.type != kChange ||
          (!builds_.empty() && builds_.back().number == r.change && r.change != 0))
        continue;
      const std::string lib(r.library);
      builds_.push_back({r.change, lib, find_library_build(file, lib, r.crc32, r.size)});
      if (r.change != 0) continue;
      const auto& libs = rt.libraries();
      auto it =
          std::find_if(libs.begin(), libs.end(), [&](const auto& l) { return l->path() == lib; });
      if (it == libs.end())
        throw RecordingError("'" + file + "' was recorded on a cell that loads the library " + lib +
                             "; this cell does not");
      // The cell runs another build than the recording began with: switch
      // to that one before the first scan.
      if ((*it)->crc32() != r.crc32 || (*it)->size() != r.size) switch_build(builds_.back(), true);
    }
    total_scans_ = check.scans();
  }
  pending_.resize(rt.tasks().size());
  rt.set_plugins_enabled(false);
  rt.add_hooks(this);
}

Replayer::~Replayer() {
  change_.reset();  // a change still under way is taken back (or finished)
  rt_.remove_hooks(this);
}

// The online change the recording made, from the same build.
void Replayer::switch_build(const Build& b, bool now) {
  auto change = std::make_unique<OnlineChange>(rt_);
  const ChangeReport r = change->prepare(b.library, b.file);
  if (!r.refused.empty())
    throw RecordingError("the replay cannot switch to the recorded build of " + b.library + " (" +
                         b.file + "): " + r.refused);
  if (now) {
    change->switch_all_now();
    change->finish();
  } else {
    change->commit();
    change_ = std::move(change);
  }
}

void Replayer::diverged(const std::string& what) {
  if (error_.empty()) error_ = "replay diverged at scan " + std::to_string(scans_) + ": " + what;
}

bool Replayer::step() {
  if (end_) return false;
  try {
    while (reader_->next(rec_)) {
      // The start builds: switched to in the constructor.
      if (rec_.type == kChange && rec_.task == kNoTask) continue;
      TaskRuntime& t = *rt_.tasks()[rec_.task];
      if (rec_.type == kChange) {
        if (rec_.change != change_number_) {
          change_number_ = rec_.change;
          if (change_) {
            diverged("the previous online change had not reached every task");
            break;
          }
          auto b = std::find_if(builds_.begin(), builds_.end(),
                                [&](const Build& x) { return x.number == rec_.change; });
          if (b == builds_.end()) {
            diverged("the recording changed to a build it did not note first");
            break;
          }
          switch_build(*b, false);
        }
        // The task switches at its next latch (Runtime::scan_latch), as recorded.
        if (!t.swap.load()) {
          diverged("the recording switched task '" + t.name +
                   "' to a new build here, the replay's change does not concern it");
          break;
        }
        continue;
      }
      if (rec_.type == kStop) {
        rt_.stop_task(t, "stopped in the recording (" + std::string(rec_.reason) + ")");
        continue;
      }
      if (t.stopped.load()) {
        diverged("task '" + t.name + "' stopped in the replay but ran on in the recording");
        break;
      }
      if (rec_.type == kLatch) {
        t.cycle = rec_.cycle;
        pending_[rec_.task] = rt_.latch_scan(t, TIME(rec_.time_ns));
      } else if (rec_.type == kMerge) {
        rt_.finish_scan(t, pending_[rec_.task]);
        if (change_ && change_->switched()) {
          change_->finish();
          change_.reset();
        }
        return true;
      }
    }
  } catch (const RecordingError& e) {
    error_ = e.what();  // the file changed after it was checked
  }
  rec_ = Record{};
  end_ = true;
  return false;
}

void Replayer::restore_snapshot(std::span<const std::uint8_t> s) {
  In in(s);
  std::uint32_t nvars = 0;
  in.le(nvars);
  alignas(8) unsigned char value[sizeof(STRING)];
  for (std::uint32_t i = 0; i < nvars; ++i) {
    std::uint16_t len = 0;
    std::uint8_t type = 0;
    std::span<const std::uint8_t> path;
    if (!in.le(len) || !in.take(len, path) || !in.le(type)) return;
    const std::string p(reinterpret_cast<const char*>(path.data()), path.size());
    const VarInfo* v = rt_.vars().find(p);
    if (!v || v->address || static_cast<std::uint8_t>(v->type) != type) {
      diverged("the recording's state has a variable this cell lacks: " + p);
      if (!skip_value(in, type)) return;
      continue;
    }
    void* dst = v->type == VarType::STRING ? static_cast<void*>(new (value) STRING()) : value;
    if (!get_value(in, v->type, dst)) return;
    VarRegistry::write(*v, dst);
  }
  for (io::Area a : {io::Area::Input, io::Area::Output, io::Area::Memory}) {
    std::uint32_t n = 0;
    std::span<const std::uint8_t> bytes;
    auto area = rt_.image().area(a);
    if (!in.le(n) || !in.take(n, bytes) || n != area.size()) return;
    std::memcpy(area.data(), bytes.data(), n);
  }
  for (const DeviceRuntime& d : rt_.devices()) {
    std::uint32_t seq = 0;
    if (!in.le(seq)) return;
    d.plugin->link(d.index).set_last_seq(seq);
  }
}

// Makes the debugger writes of the recorded scan that belong to this hook
// point again (the reader checked their bounds).
void Replayer::apply_events(TaskRuntime& t, Point point, std::size_t index) {
  if (rec_.task != t.order || rec_.event_groups == 0) return;
  In in(rec_.events);
  alignas(8) unsigned char value[sizeof(STRING)];
  for (std::uint16_t g = 0; g < rec_.event_groups; ++g) {
    std::uint8_t p = 0;
    std::uint16_t idx = 0, n = 0;
    if (!in.le(p) || !in.le(idx) || !in.le(n)) return;
    const bool here = p == point && idx == index;
    for (std::uint16_t k = 0; k < n; ++k) {
      std::uint8_t target = 0, type = 0;
      if (!in.le(target)) return;
      VarInfo dst;
      const VarInfo* var = nullptr;
      if (target == kVariable) {
        std::uint16_t len = 0;
        std::span<const std::uint8_t> path;
        if (!in.le(len) || !in.take(len, path) || !in.le(type)) return;
        const std::string name(reinterpret_cast<const char*>(path.data()), path.size());
        var = here ? rt_.vars().find(name) : nullptr;
        if (here && (!var || var->address || static_cast<std::uint8_t>(var->type) != type)) {
          diverged("the recording writes a variable this cell lacks: " + name);
          var = nullptr;
        }
      } else {
        std::uint8_t area = 0, bit = 0, order = 0;
        std::uint32_t byte = 0;
        if (!in.le(area) || !in.le(byte) || !in.le(bit) || !in.le(type) || !in.le(order)) return;
        dst.type = static_cast<VarType>(type);
        dst.address = io::IecAddress{static_cast<io::Area>(area), io::AddrSize::Byte, byte, bit};
        io::ProcessImage& image = target == kGlobalImage ? rt_.image() : t.image;
        dst.image_ptr = image.area(dst.address->area).data() + byte;
        dst.order = static_cast<io::ByteOrder>(order);
        var = &dst;
      }
      const auto vt = static_cast<VarType>(type);
      void* buf = vt == VarType::STRING ? static_cast<void*>(new (value) STRING()) : value;
      if (!get_value(in, vt, buf)) return;
      if (here && var) VarRegistry::write(*var, buf);
    }
  }
}

void Replayer::after_latch(TaskRuntime& t, io::ProcessImage& global) {
  if (rec_.type != kLatch || rec_.task != t.order) return;
  if (!rec_.snapshot.empty()) restore_snapshot(rec_.snapshot);
  const auto& devs = rt_.devices();
  for (std::size_t i = 0; i < devs.size() && i < rec_.states.size(); ++i)
    devs[i].plugin->link(devs[i].index).force_state(static_cast<io::DeviceState>(rec_.states[i]));
  // Answer the replayed program's requests as the devices answered the
  // recorded one: same device, same submission number, same data.
  In in(rec_.answers);
  for (std::uint16_t k = 0; k < rec_.answer_count; ++k) {
    std::uint16_t dev = 0, err = 0, len = 0;
    std::uint32_t seq = 0;
    std::uint8_t st = 0;
    std::span<const std::uint8_t> data;
    if (!in.le(dev) || !in.le(seq) || !in.le(st) || !in.le(err) || !in.le(len) ||
        !in.take(len, data))
      break;
    io::DeviceLink& link = devs[dev].plugin->link(devs[dev].index);
    io::RecordRequest* r = link.pop();
    if (!r || r->seq() != seq)
      diverged("device '" + devs[dev].name + "' has no request " + std::to_string(seq) +
               " waiting (front " + std::to_string(r ? r->seq() : 0) + ")");
    if (r) {
      r->finish_as(static_cast<io::RecordStatus>(st), err, data);
      link.untrack(r);
    }
  }
  auto gi = global.area(io::Area::Input);
  std::size_t off = 0;
  for (const DeviceRuntime* d : t.devices) {
    std::memcpy(gi.data() + d->in.byte, rec_.inputs.data() + off, d->sizes.input_bytes);
    off += d->sizes.input_bytes;
  }
  apply_events(t, kAfterLatch, 0);
}

void Replayer::before_programs(TaskRuntime& t, const ScanContext&) {
  if (rec_.type == kMerge) apply_events(t, kBeforePrograms, 0);
}

void Replayer::before_program(TaskRuntime& t, std::size_t index, const ScanContext&) {
  if (rec_.type == kMerge) apply_events(t, kBeforeProgram, index);
}

void Replayer::after_programs(TaskRuntime& t, const ScanContext&) {
  if (rec_.type == kMerge) apply_events(t, kAfterPrograms, 0);
}

void Replayer::before_publish(TaskRuntime& t, io::ProcessImage& global) {
  if (rec_.type != kMerge || rec_.task != t.order) return;
  apply_events(t, kBeforePublish, 0);
  if (image_hash(global.area(io::Area::Output), global.area(io::Area::Memory)) != rec_.hash) {
    ++mismatches_;
    if (first_mismatch_ < 0) first_mismatch_ = static_cast<std::int64_t>(scans_);
  }
  ++scans_;
}

}  // namespace plc::debug

// The recorder: scan hooks that copy each scan's inputs, the debugger's
// writes and the order of the image-locked halves into records, and hand
// them to the writer thread (format and guarantees: recording.hpp).
#include "plc/debug/recording.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "image_mirror.hpp"
#include "plc/cell_library.hpp"
#include "plc/io/device_link.hpp"
#include "recording_writer.hpp"

namespace plc::debug {

using namespace recfmt;

namespace {

// Room for the debugger's writes in one scan (per task): a few hundred
// forced variables. More fail the recording with a clear error.
constexpr std::size_t kEventBytes = 64 << 10;
// The writer's blocks: at least this big, and this many. In real time the
// disk may fall behind by all of them before records are lost.
constexpr std::size_t kMinBlockBytes = 256 << 10;
constexpr std::size_t kBlocks = 32;
// Answers one latch can deliver: every request a device tracks.
constexpr std::size_t kAnswerBytes = 4 * io::DeviceLink::kQueueDepth * (11 + io::kRecordMaxBytes);

constexpr std::size_t kMaxValueBytes = 1 + STRING::capacity;

}  // namespace

Recorder::Recorder(Runtime& rt, const std::string& file, Attach attach)
    : rt_(rt), file_(file), attached_(attach == Attach::Self), tasks_(rt.tasks().size()) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    throw std::runtime_error("cannot write recording '" + file + "': " + std::strerror(errno));
  for (TaskRec& ts : tasks_) {
    ts.merge.reserve_fixed(kEventBytes + 64);
    ts.pending.reserve_fixed(kEventBytes);
  }
  std::size_t inputs = 0;
  for (const auto& t : rt.tasks()) {
    std::size_t n = 0;
    for (const DeviceRuntime* d : t->devices) n += d->sizes.input_bytes;
    inputs = std::max(inputs, n);
  }
  const std::size_t ndev = rt.devices().size();
  answers_.reserve_fixed(ndev * kAnswerBytes);
  const std::size_t shared = 64 + 14 * rt.tasks().size() + inputs + ndev + ndev * kAnswerBytes +
                             kEventBytes + snapshot_bytes() + kMaxPathBytes;
  shared_.reserve_fixed(shared);
  const io::ImageSizes sizes = rt.image().sizes();
  mirror_ = std::make_unique<ImageMirror>(sizes.outputs, sizes.memory);
  const std::size_t delta = kHead + mirror_->max_delta_bytes() + kTail;
  delta_.reserve_fixed(delta);
  // What each task's merge can change in the global %Q and %M: its bound
  // bytes (an online change cannot move them; ranges sorted and more than
  // a word apart, Runtime's build joins closer ones). The debugger's writes
  // add their words as they are made (note_write).
  for (const auto& t : rt.tasks()) {
    TaskRec& ts = tasks_[t->order];
    for (const DeviceRuntime* d : t->devices) ts.input_bytes += d->sizes.input_bytes;
    for (io::Area a : {io::Area::Output, io::Area::Memory})
      for (const ImageRange& r : t->bound[static_cast<std::size_t>(a)])
        if (const Words w = mirror_->words_of(a == io::Area::Output, r.begin, r.end - r.begin);
            w.begin != w.end)
          ts.bound.push_back(w);
  }
  writer_ = std::make_unique<RecordingWriter>(
      fd, file, std::string(kMagic, sizeof kMagic),
      std::max({kMinBlockBytes, shared + kEventBytes + 64, delta}), kBlocks,
      std::make_unique<ImageMirror>(sizes.outputs, sizes.memory));

  const RecordingLayout l = RecordingLayout::of(rt);
  shared_.begin(kHeader);
  shared_.le(l.layout_hash);
  for (std::uint32_t s : l.image_bytes) shared_.le(s);
  shared_.le(l.devices);
  shared_.le(static_cast<std::uint16_t>(l.tasks.size()));
  for (const RecordingLayout::Task& t : l.tasks) {
    shared_.le(t.period_ns);
    shared_.le(t.input_bytes);
    shared_.le(t.programs);
  }
  shared_.end();
  commit(shared_, true);
  // The builds of the cell libraries the recording begins with.
  for (const auto& lib : rt.libraries()) {
    keep_copy(*lib);
    put_change(shared_, kNoTask, 0, *lib, "");
    commit(shared_, true);
  }
  if (attached_) {
    arm();
    rt_.add_hooks(this);
  }
}

Recorder::~Recorder() {
  if (closed_) return;
  const std::string err = close();
  if (!err.empty())
    std::fprintf(stderr, "plcrun: recording '%s' failed: %s\n", file_.c_str(), err.c_str());
}

std::size_t Recorder::snapshot_bytes() const {
  std::size_t n = 4 + 3 * 4;
  for (const VarInfo& v : rt_.vars().all())
    if (!v.address) n += 2 + v.path.size() + 1 + kMaxValueBytes;
  const io::ImageSizes s = rt_.image().sizes();
  return n + s.inputs + s.outputs + s.memory;
}

void Recorder::arm() {
  for (const auto& t : rt_.tasks()) {
    TaskRec& ts = tasks_[t->order];
    const bool in_scan = t->scan_started_ns.load(std::memory_order_acquire) >= 0;
    ts.state = in_scan && !t->stopped.load() ? TaskRec::Busy : TaskRec::Idle;
    ts.pending.clear();
    ts.pending_count = 0;
  }
}

void Recorder::fail(const std::string& why) {
  std::lock_guard<std::mutex> lock(error_mu_);
  if (error_.empty()) error_ = why;
  dead_.store(true, std::memory_order_release);
}

void Recorder::commit(const Buf& b, bool wait) {
  if (dead_.load(std::memory_order_acquire)) return;
  if (b.overflow()) {
    fail("a scan's record did not fit the recording's buffer (more than " +
         std::to_string(kEventBytes) + " bytes of debugger writes in one scan?)");
    return;
  }
  if (!writer_->append(b.view(), wait)) {
    fail(writer_->error());
    return;
  }
  ++records_;
}

// The recording starts at a latch at which no other task is inside a scan:
// then every other task's next locked section is recorded, and the
// snapshot (taken now, under the image lock) reads no variable a running
// program is changing.
bool Recorder::try_start(const TaskRuntime& t) {
  for (const auto& u : rt_.tasks()) {
    if (u.get() == &t || u->stopped.load(std::memory_order_acquire)) continue;
    if (tasks_[u->order].state != TaskRec::Idle) return false;
  }
  // Started mid-session, the replay begins from a snapshot of the programs'
  // declared state, which cannot hold an acyclic request on its way (the
  // request objects, the device's queue): start at a latch with none in
  // flight and none answered. From scan 0 that is the first latch.
  if (answer_count_ != 0) return false;
  for (const DeviceRuntime& d : rt_.devices())
    if (d.link->in_flight() != 0) return false;
  active_ = true;
  return true;
}

void Recorder::after_latch(TaskRuntime& t, io::ProcessImage& global) {
  TaskRec& ts = tasks_[t.order];
  auto drop = [&] {
    ts.pending.clear();
    ts.pending_count = 0;
    answers_.clear();
    answer_count_ = 0;
  };
  const bool first = !active_;
  if (dead_.load(std::memory_order_acquire) || (first && !try_start(t))) {
    ts.state = TaskRec::Busy;
    drop();
    return;
  }
  if (ts.pending.overflow() || answers_.overflow())
    fail("a latch's answers or debugger writes did not fit the recording's buffer");
  // An online change switched this task at this latch (Runtime::scan_latch).
  if (ts.change_due.load(std::memory_order_acquire)) {
    commit(ts.change, rt_.mode() == io::ClockMode::Virtual);
    ts.change_due.store(false, std::memory_order_release);
    // The new build binds the same bytes (an online change cannot move
    // them), and the values it carries over go into them; compared whole
    // once all the same, since a change happens rarely.
    diff_whole_next();
  }
  // The record's fields through a cursor, into room checked for once.
  const auto& devs = rt_.devices();
  Buf& b = shared_;
  b.clear();
  const std::size_t most = kHead + 2 + 8 + 8 + ts.input_bytes + 2 + devs.size() + 2 +
                           answers_.size() + 2 + 1 + 2 + 2 + ts.pending.size() + 1;
  if (std::uint8_t* room = b.room(most)) {
    Put c{room};
    c.u8(kLatch);
    c.le(std::uint32_t{0});  // the length: end()
    c.le(static_cast<std::uint16_t>(t.order));
    c.le(t.cycle);
    c.le(static_cast<std::int64_t>(t.scan_time.count()));
    const std::uint8_t* in = global.area(io::Area::Input).data();
    for (const DeviceRuntime* d : t.devices) c.bytes(in + d->in.byte, d->sizes.input_bytes);
    // Device states as the programs see them (a device's state changes
    // only at its own task's latch).
    c.le(static_cast<std::uint16_t>(devs.size()));
    for (const DeviceRuntime& d : devs) c.u8(static_cast<std::uint8_t>(d.link->state()));
    c.le(answer_count_);
    c.bytes(answers_.view().data(), answers_.size());
    if (ts.pending_count) {
      c.le(std::uint16_t{1});
      c.u8(kAfterLatch);
      c.le(std::uint16_t{0});
      c.le(ts.pending_count);
      c.bytes(ts.pending.view().data(), ts.pending.size());
    } else {
      c.le(std::uint16_t{0});
    }
    c.u8(first ? 1 : 0);
    b.advance_to(c.p);
  }
  if (first) put_snapshot(b);
  b.end();
  commit(b, rt_.mode() == io::ClockMode::Virtual);
  drop();
  ts.state = TaskRec::Open;
  Buf& mg = ts.merge;
  mg.clear();
  if (std::uint8_t* room = mg.room(kHead + 4)) {
    Put c{room};
    c.u8(kMerge);
    c.le(std::uint32_t{0});
    c.le(static_cast<std::uint16_t>(t.order));
    c.le(std::uint16_t{0});  // event groups, filled in at the merge
    mg.advance_to(c.p);
  }
  ts.merge_groups = 0;
}

void Recorder::on_answer(TaskRuntime&, std::size_t device, const io::RecordRequest& r) {
  ++answer_count_;
  answers_.le(static_cast<std::uint16_t>(device));
  answers_.le(r.seq());
  answers_.u8(static_cast<std::uint8_t>(r.status()));
  answers_.le(r.error_code());
  const auto data = r.data();
  answers_.le(static_cast<std::uint16_t>(data.size()));
  answers_.bytes(data.data(), data.size());
}

// The snapshot: every reflected program variable (located ones live in the
// images), the global %I, %Q, %M, then each device's last request number.
void Recorder::put_snapshot(Buf& b) {
  std::uint32_t n = 0;
  for (const VarInfo& v : rt_.vars().all()) n += v.address ? 0 : 1;
  b.le(n);
  for (const VarInfo& v : rt_.vars().all()) {
    if (v.address) continue;
    b.le(static_cast<std::uint16_t>(v.path.size()));
    b.bytes(v.path.data(), v.path.size());
    b.u8(static_cast<std::uint8_t>(v.type));
    put_value(b, v.type, v.ptr);
  }
  for (io::Area a : {io::Area::Input, io::Area::Output, io::Area::Memory}) {
    auto s = rt_.image().area(a);
    b.le(static_cast<std::uint32_t>(s.size()));
    b.bytes(s.data(), s.size());
  }
  for (const DeviceRuntime& d : rt_.devices()) b.le(d.link->last_seq());
}

void Recorder::mark(Marks& m, bool output, std::size_t byte, std::size_t n) {
  if (m.n == kMarks) {
    diff_whole_next();
    return;
  }
  m.w[m.n++] = mirror_->words_of(output, byte, n);
}

void Recorder::note_write(TaskRuntime& t, const VarInfo& v, const void* value) {
  TaskRec& ts = tasks_[t.order];
  Buf& p = ts.pending;
  if (v.address) {
    const bool in_task = v.image_ptr == t.image.at(*v.address);
    const bool in_global = !in_task && v.image_ptr == rt_.image().at(*v.address);
    // The words the next diffs must look at: a write into the global
    // image is there for the next diff of any task (under the image lock
    // both); one into t's copy reaches the global image at t's merge; one
    // into another task's copy (not recorded: overwritten at that task's
    // next latch) is not followed word by word.
    if (v.address->area != io::Area::Input) {
      const bool output = v.address->area == io::Area::Output;
      const std::size_t n = v.address->width_bytes();
      if (in_global)
        mark(marks_, output, v.address->byte, n);
      else if (in_task)
        mark(ts.marks, output, v.address->byte, n);
      else
        diff_whole_next();
    }
    if (!in_task && !in_global) return;
    const std::uint8_t target = in_task ? kTaskImage : kGlobalImage;
    p.u8(target);
    p.u8(static_cast<std::uint8_t>(v.address->area));
    p.le(v.address->byte);
    p.u8(v.address->bit);
    p.u8(static_cast<std::uint8_t>(v.type));
    p.u8(static_cast<std::uint8_t>(v.order));
  } else {
    if (v.path.size() > kMaxPathBytes) {
      fail("variable path longer than " + std::to_string(kMaxPathBytes) + " bytes: " + v.path);
      return;
    }
    p.u8(kVariable);
    p.le(static_cast<std::uint16_t>(v.path.size()));
    p.bytes(v.path.data(), v.path.size());
    p.u8(static_cast<std::uint8_t>(v.type));
  }
  put_value(p, v.type, value);
  ++ts.pending_count;
}

// Gives the debugger writes noted since the last hook of t's scan the hook
// point that has just come.
void Recorder::seal(TaskRec& ts, Point point, std::size_t index) {
  if (ts.pending_count && ts.state == TaskRec::Open) {
    if (ts.pending.overflow()) fail("a scan's debugger writes did not fit the recording's buffer");
    ts.merge.u8(point);
    ts.merge.le(static_cast<std::uint16_t>(index));
    ts.merge.le(ts.pending_count);
    ts.merge.bytes(ts.pending.view().data(), ts.pending.size());
    ++ts.merge_groups;
  }
  ts.pending.clear();
  ts.pending_count = 0;
}

// With no debugger write noted (nearly every scan), a seal has nothing to
// seal: pending_count 0 means an empty, not overflowed, buffer.
void Recorder::before_programs(TaskRuntime& t, const ScanContext&) {
  TaskRec& ts = tasks_[t.order];
  if (ts.pending_count) seal(ts, kBeforePrograms, 0);
}

void Recorder::before_program(TaskRuntime& t, std::size_t index, const ScanContext&) {
  TaskRec& ts = tasks_[t.order];
  if (ts.pending_count) seal(ts, kBeforeProgram, index);
}

void Recorder::after_programs(TaskRuntime& t, const ScanContext&) {
  TaskRec& ts = tasks_[t.order];
  if (ts.pending_count) seal(ts, kAfterPrograms, 0);
}

void Recorder::before_publish(TaskRuntime& t, io::ProcessImage& global) {
  TaskRec& ts = tasks_[t.order];
  if (ts.state != TaskRec::Open) {
    // Merged unrecorded (the recording starts, or failed): what it changed
    // is for the next diffs to find.
    ts.state = TaskRec::Idle;
    seal(ts, kBeforePublish, 0);  // drops them
    ts.marks.n = 0;
    diff_whole_next();
    return;
  }
  if (ts.pending_count) seal(ts, kBeforePublish, 0);
  ts.merge.patch(kHead + 2, ts.merge_groups);
  ts.merge.le(std::uint64_t{0});  // the output hash: the writer's, from the deltas
  ts.merge.end();
  const bool wait = rt_.mode() == io::ClockMode::Virtual;
  // Since the last diff (of any task) only this scan's merge and the
  // debugger's writes changed %Q and %M: the words they can have changed
  // are compared (none for a task bound to no %Q/%M byte), unless
  // something else wrote them (then all).
  const auto q = global.area(io::Area::Output);
  const auto m = global.area(io::Area::Memory);
  std::uint32_t words = 0;
  if (const std::uint64_t e = whole_epoch_.load(std::memory_order_relaxed); ts.whole_seen != e) {
    ts.whole_seen = e;
    delta_.begin(kImageDelta);
    words = mirror_->diff(q, m, delta_);
  } else if (!ts.bound.empty() || ts.marks.n != 0 || marks_.n != 0) {
    delta_.begin(kImageDelta);
    words = mirror_->diff_words(q, m,
                                {std::span<const Words>(ts.bound),
                                 {ts.marks.w.data(), ts.marks.n},
                                 {marks_.w.data(), marks_.n}},
                                delta_);
  }
  ts.marks.n = 0;
  marks_.n = 0;
  if (words != 0) {
    delta_.end();
    // Not a record of the file: not counted, and no CRC of its own.
    if (!dead_.load(std::memory_order_acquire) && !writer_->append(delta_.view(), wait))
      fail(writer_->error());
  }
  commit(ts.merge, wait);
  ts.state = TaskRec::Idle;
  scans_.fetch_add(1, std::memory_order_relaxed);
}

void Recorder::on_stop(TaskRuntime& t, io::ProcessImage&) {
  diff_whole_next();  // the stopped task's outputs went to their safe values
  if (!active_) return;
  const std::string_view why = t.stats.stop_reason();
  const std::size_t n = std::min<std::size_t>(why.size(), kMaxPathBytes);
  shared_.begin(kStop);
  shared_.le(static_cast<std::uint16_t>(t.order));
  shared_.le(static_cast<std::uint16_t>(n));
  shared_.bytes(why.data(), n);
  shared_.end();
  commit(shared_, rt_.mode() == io::ClockMode::Virtual);
}

std::string Recorder::close() {
  if (!closed_) {
    closed_ = true;
    if (attached_) rt_.remove_hooks(this);
    shared_.begin(kEnd);
    shared_.le(scans_.load());
    shared_.le(records_);
    shared_.end();
    commit(shared_, true);
    const std::string err = writer_->finish();
    if (!err.empty()) fail(err);
  }
  std::lock_guard<std::mutex> lock(error_mu_);
  return error_;
}

}  // namespace plc::debug

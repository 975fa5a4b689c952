#include "plc/debug/recording.hpp"

#include <algorithm>
#include <cstring>
#include <span>
#include <stdexcept>

namespace plc::debug {
namespace {

constexpr char kMagic[8] = {'P', 'L', 'C', 'R', 'E', 'C', '0', '3'};

template <class T>
void put(std::vector<std::uint8_t>& b, T v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  b.insert(b.end(), p, p + sizeof v);
}

template <class T>
bool get(std::FILE* f, T& v) {
  return std::fread(&v, sizeof v, 1, f) == 1;
}

void put_bytes(std::vector<std::uint8_t>& b, std::span<const std::uint8_t> s) {
  put(b, static_cast<std::uint32_t>(s.size()));
  b.insert(b.end(), s.begin(), s.end());
}

// The areas a snapshot holds, in order: the scanning task's private image
// (I, Q, M), its scan-start copy (Q, M), and the global image (I, Q, M).
std::vector<std::span<std::uint8_t>> snapshot_areas(TaskRuntime& t, io::ProcessImage& global) {
  using io::Area;
  return {t.image.area(Area::Input),   t.image.area(Area::Output),  t.image.area(Area::Memory),
          t.before.area(Area::Output), t.before.area(Area::Memory), global.area(Area::Input),
          global.area(Area::Output),   global.area(Area::Memory)};
}

std::size_t stored_size(const VarInfo& v) {
  return v.type == VarType::STRING ? sizeof(STRING) : size_of(v.type);
}

std::uint64_t output_hash(const TaskRuntime& t, io::ProcessImage& global) {
  std::uint64_t h = 1469598103934665603ULL;
  auto q = global.area(io::Area::Output);
  for (const DeviceRuntime* d : t.devices)
    h = fnv1a(q.data() + d->out.byte, d->sizes.output_bytes, h);
  return h;
}

}  // namespace

std::uint64_t fnv1a(const std::uint8_t* p, std::size_t n, std::uint64_t h) {
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ULL;
  return h;
}

Recorder::Recorder(Runtime& rt, const std::string& file) : rt_(rt) {
  f_ = std::fopen(file.c_str(), "wb");
  if (!f_) throw std::runtime_error("cannot write recording '" + file + "'");
  buf_.reserve(1 << 17);
  buf_.insert(buf_.end(), kMagic, kMagic + 8);
  put(buf_, rt.layout_hash());
  rt_.add_hooks(this);
}

Recorder::~Recorder() { close(); }

void Recorder::close() {
  if (!f_) return;
  rt_.remove_hooks(this);
  flush();
  std::fclose(f_);
  f_ = nullptr;
}

void Recorder::flush() {
  if (f_ && !buf_.empty()) std::fwrite(buf_.data(), 1, buf_.size(), f_);
  buf_.clear();
}

void Recorder::after_latch(TaskRuntime& t, io::ProcessImage& global) {
  buf_.push_back('S');
  put(buf_, static_cast<std::uint16_t>(t.order));
  put(buf_, rt_.now().count());
  auto in = global.area(io::Area::Input);
  for (const DeviceRuntime* d : t.devices)
    buf_.insert(buf_.end(), in.begin() + d->in.byte,
                in.begin() + d->in.byte + d->sizes.input_bytes);
  // Device states (as the programs see them) and the acyclic answers this
  // scan is the first to see (collected by on_answer during the latch).
  const auto& devs = rt_.devices();
  buf_.push_back(static_cast<std::uint8_t>(devs.size()));
  for (const DeviceRuntime& d : devs)
    buf_.push_back(static_cast<std::uint8_t>(d.plugin->link(d.index).state()));
  put(buf_, answer_count_);
  buf_.insert(buf_.end(), answers_.begin(), answers_.end());
  answers_.clear();
  answer_count_ = 0;
}

void Recorder::on_answer(TaskRuntime&, std::size_t device, const io::RecordRequest& r) {
  ++answer_count_;
  put(answers_, static_cast<std::uint16_t>(device));
  put(answers_, r.seq());
  answers_.push_back(static_cast<std::uint8_t>(r.status()));
  put(answers_, r.error_code());
  const auto data = r.data();
  put(answers_, static_cast<std::uint16_t>(data.size()));
  answers_.insert(answers_.end(), data.begin(), data.end());
}

void Recorder::before_programs(TaskRuntime& t, const ScanContext&) {
  if (scans_ > 0) {
    buf_.push_back(0);
    return;
  }
  buf_.push_back(1);
  std::uint32_t n = 0;
  for (const VarInfo& v : rt_.vars().all()) n += v.address ? 0 : 1;
  put(buf_, n);
  for (const VarInfo& v : rt_.vars().all()) {
    if (v.address) continue;  // located variables live in the images below
    put(buf_, static_cast<std::uint16_t>(v.path.size()));
    buf_.insert(buf_.end(), v.path.begin(), v.path.end());
    const auto* p = static_cast<const std::uint8_t*>(v.ptr);
    put_bytes(buf_, {p, stored_size(v)});
  }
  for (auto area : snapshot_areas(t, rt_.image())) put_bytes(buf_, area);
  put(buf_, static_cast<std::uint32_t>(rt_.tasks().size()));
  for (const auto& task : rt_.tasks()) put(buf_, task->cycle);
}

void Recorder::before_publish(TaskRuntime& t, io::ProcessImage& global) {
  put(buf_, output_hash(t, global));
  ++scans_;
  if (buf_.size() > (1 << 16)) flush();
}

Replayer::Replayer(Runtime& rt, const std::string& file) : rt_(rt) {
  f_ = std::fopen(file.c_str(), "rb");
  if (!f_) throw std::runtime_error("cannot read recording '" + file + "'");
  char magic[8];
  std::uint64_t layout = 0;
  if (std::fread(magic, 1, 8, f_) != 8 || std::memcmp(magic, kMagic, 8) != 0 || !get(f_, layout)) {
    std::fclose(f_);
    throw std::runtime_error("'" + file + "' is not a recording (bad header)");
  }
  if (layout != rt.layout_hash()) {
    std::fclose(f_);
    throw std::runtime_error("'" + file +
                             "' was recorded on a different cell layout (tasks or devices differ)");
  }
  std::size_t most = 0;
  for (const auto& t : rt.tasks()) {
    std::size_t n = 0;
    for (const DeviceRuntime* d : t->devices) n += d->sizes.input_bytes;
    most = std::max(most, n);
  }
  inputs_.resize(most);
  rt.set_plugins_enabled(false);
  rt.add_hooks(this);
}

Replayer::~Replayer() {
  rt_.remove_hooks(this);
  if (f_) std::fclose(f_);
}

bool Replayer::step() {
  if (end_) return false;
  std::uint8_t tag = 0;
  std::uint16_t task = 0;
  std::int64_t now = 0;
  if (!get(f_, tag)) {
    end_ = true;
    return false;
  }
  if (tag != 'S' || !get(f_, task) || !get(f_, now) || task >= rt_.tasks().size()) {
    error_ = "corrupt recording at scan " + std::to_string(scans_);
    end_ = true;
    return false;
  }
  TaskRuntime& t = *rt_.tasks()[task];
  std::size_t n = 0;
  for (const DeviceRuntime* d : t.devices) n += d->sizes.input_bytes;
  std::uint8_t has_snapshot = 0;
  if (std::fread(inputs_.data(), 1, n, f_) != n || !read_states_and_answers() ||
      !get(f_, has_snapshot) || (has_snapshot && !read_snapshot()) || !get(f_, expected_hash_)) {
    if (error_.empty()) error_ = "recording ends inside scan " + std::to_string(scans_);
    end_ = true;
    return false;
  }
  if (!snapshot_.empty()) {
    // Task cycle counters go back before the scan starts: its ScanContext
    // is made before the hooks run.
    const std::size_t nt = rt_.tasks().size();
    const std::uint8_t* p = snapshot_.data() + snapshot_.size() - nt * sizeof(std::uint64_t);
    for (std::size_t i = 0; i < nt; ++i)
      std::memcpy(&rt_.tasks()[i]->cycle, p + i * sizeof(std::uint64_t), sizeof(std::uint64_t));
  }
  rt_.run_scan(t, TIME(now));
  return true;
}

// Reads this scan's device states and acyclic answers (applied in
// after_latch).
bool Replayer::read_states_and_answers() {
  std::uint8_t ndev = 0;
  std::uint16_t nans = 0;
  if (!get(f_, ndev) || ndev != rt_.devices().size()) return false;
  states_.resize(ndev);
  if (std::fread(states_.data(), 1, ndev, f_) != ndev || !get(f_, nans)) return false;
  answers_.clear();
  for (std::uint16_t k = 0; k < nans; ++k) {
    std::uint8_t head[2 + 4 + 1 + 2 + 2];
    if (std::fread(head, 1, sizeof head, f_) != sizeof head) return false;
    std::uint16_t len;
    std::memcpy(&len, head + 9, sizeof len);
    answers_.insert(answers_.end(), head, head + sizeof head);
    const std::size_t at = answers_.size();
    answers_.resize(at + len);
    if (std::fread(answers_.data() + at, 1, len, f_) != len) return false;
  }
  return true;
}

// Reads the snapshot block into snapshot_ (restored in before_programs).
bool Replayer::read_snapshot() {
  snapshot_.clear();
  auto take = [this](std::size_t n) {
    const std::size_t at = snapshot_.size();
    snapshot_.resize(at + n);
    return std::fread(snapshot_.data() + at, 1, n, f_) == n;
  };
  auto take_u32 = [&](std::uint32_t& v) {
    if (!take(sizeof v)) return false;
    std::memcpy(&v, snapshot_.data() + snapshot_.size() - sizeof v, sizeof v);
    return true;
  };
  std::uint32_t nvars = 0;
  if (!take_u32(nvars)) return false;
  for (std::uint32_t i = 0; i < nvars; ++i) {
    std::uint16_t len = 0;
    std::uint32_t size = 0;
    if (!take(sizeof len)) return false;
    std::memcpy(&len, snapshot_.data() + snapshot_.size() - sizeof len, sizeof len);
    if (!take(len) || !take_u32(size) || !take(size)) return false;
  }
  for (int a = 0; a < 8; ++a) {
    std::uint32_t size = 0;
    if (!take_u32(size) || !take(size)) return false;
  }
  std::uint32_t ntasks = 0;
  if (!take_u32(ntasks) || !take(std::size_t(ntasks) * sizeof(std::uint64_t))) return false;
  return true;
}

void Replayer::before_programs(TaskRuntime& t, const ScanContext&) {
  if (snapshot_.empty()) return;
  const std::uint8_t* p = snapshot_.data();
  auto u32 = [&p] {
    std::uint32_t v;
    std::memcpy(&v, p, sizeof v);
    p += sizeof v;
    return v;
  };
  const std::uint32_t nvars = u32();
  for (std::uint32_t i = 0; i < nvars; ++i) {
    std::uint16_t len;
    std::memcpy(&len, p, sizeof len);
    p += sizeof len;
    const std::string path(reinterpret_cast<const char*>(p), len);
    p += len;
    const std::uint32_t size = u32();
    const VarInfo* v = rt_.vars().find(path);
    if (v && !v->address && stored_size(*v) == size)
      std::memcpy(v->ptr, p, size);
    else if (error_.empty())
      error_ = "the recording's state has a variable this cell lacks: " + path;
    p += size;
  }
  for (auto area : snapshot_areas(t, rt_.image())) {
    const std::uint32_t size = u32();
    std::memcpy(area.data(), p, std::min<std::size_t>(size, area.size()));
    p += size;
  }
  snapshot_.clear();  // the task cycle counters were restored in step()
}

void Replayer::after_latch(TaskRuntime& t, io::ProcessImage& global) {
  const auto& devs = rt_.devices();
  for (std::size_t i = 0; i < devs.size() && i < states_.size(); ++i)
    devs[i].plugin->link(devs[i].index).force_state(static_cast<io::DeviceState>(states_[i]));
  // Answer the replayed program's requests as the devices answered the
  // recorded one: same device, same submission number, same data.
  for (std::size_t p = 0; p < answers_.size();) {
    std::uint16_t dev, err, len;
    std::uint32_t seq;
    std::memcpy(&dev, &answers_[p], 2);
    std::memcpy(&seq, &answers_[p + 2], 4);
    const auto st = static_cast<io::RecordStatus>(answers_[p + 6]);
    std::memcpy(&err, &answers_[p + 7], 2);
    std::memcpy(&len, &answers_[p + 9], 2);
    const std::span<const std::uint8_t> data(answers_.data() + p + 11, len);
    p += 11 + len;
    io::RecordRequest* r =
        dev < devs.size() ? devs[dev].plugin->link(devs[dev].index).pop() : nullptr;
    if (!r || r->seq() != seq) {
      if (error_.empty())
        error_ = "replay diverged at scan " + std::to_string(scans_) + ": device '" +
                 (dev < devs.size() ? devs[dev].name : "?") + "' has no request " +
                 std::to_string(seq) + " waiting";
      if (r) r->finish_as(st, err, data);
      continue;
    }
    r->finish_as(st, err, data);
  }
  answers_.clear();
  auto in = global.area(io::Area::Input);
  std::size_t off = 0;
  for (const DeviceRuntime* d : t.devices) {
    std::memcpy(in.data() + d->in.byte, inputs_.data() + off, d->sizes.input_bytes);
    off += d->sizes.input_bytes;
  }
}

void Replayer::before_publish(TaskRuntime& t, io::ProcessImage& global) {
  if (output_hash(t, global) != expected_hash_) {
    ++mismatches_;
    if (first_mismatch_ < 0) first_mismatch_ = static_cast<std::int64_t>(scans_);
  }
  ++scans_;
}

}  // namespace plc::debug

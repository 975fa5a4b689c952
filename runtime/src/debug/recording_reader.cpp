#include "plc/debug/recording_reader.hpp"

#include <sys/stat.h>

#include <cstring>

#include "plc/io/record_request.hpp"
#include "plc/runtime.hpp"

namespace plc::debug {

using namespace recfmt;

RecordingLayout RecordingLayout::of(Runtime& rt) {
  RecordingLayout l;
  l.layout_hash = rt.layout_hash();
  const io::ImageSizes s = rt.image().sizes();
  l.image_bytes[0] = static_cast<std::uint32_t>(s.inputs);
  l.image_bytes[1] = static_cast<std::uint32_t>(s.outputs);
  l.image_bytes[2] = static_cast<std::uint32_t>(s.memory);
  l.devices = static_cast<std::uint16_t>(rt.devices().size());
  for (const auto& t : rt.tasks()) {
    std::uint32_t in = 0;
    for (const DeviceRuntime* d : t->devices)
      in += static_cast<std::uint32_t>(d->sizes.input_bytes);
    l.tasks.push_back({t->period.count(), in, static_cast<std::uint16_t>(t->programs.size())});
  }
  return l;
}

RecordingReader::RecordingReader(const std::string& path) {
  f_ = std::fopen(path.c_str(), "rb");
  struct stat st {};
  if (!f_ || ::fstat(fileno(f_), &st) != 0 || !S_ISREG(st.st_mode)) {
    if (f_) std::fclose(f_);
    f_ = nullptr;
    throw std::runtime_error("cannot read recording '" + path + "'");
  }
  size_ = static_cast<std::uint64_t>(st.st_size);
  try {
    open();
  } catch (...) {
    std::fclose(f_);  // the destructor does not run for a constructor that throws
    f_ = nullptr;
    throw;
  }
}

RecordingReader::RecordingReader(std::span<const std::uint8_t> bytes)
    : mem_(bytes), size_(bytes.size()) {
  open();
}

RecordingReader::~RecordingReader() {
  if (f_) std::fclose(f_);
}

bool RecordingReader::read(void* dst, std::size_t n) {
  if (n > size_ - pos_) return false;
  if (f_) {
    if (std::fread(dst, 1, n, f_) != n) return false;
  } else if (n) {
    std::memcpy(dst, mem_.data() + pos_, n);
  }
  pos_ += n;
  return true;
}

void RecordingReader::damaged(const std::string& what) const {
  throw RecordingError("recording damaged at scan " + std::to_string(scans_) + " (byte offset " +
                       std::to_string(record_offset_) + "): " + what);
}

void RecordingReader::open() {
  char magic[8];
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  if (!read(magic, sizeof magic) || std::memcmp(magic, kMagic, 6) != 0 || !digit(magic[6]) ||
      !digit(magic[7]))
    throw RecordingError("not a recording (no PLCREC header)");
  if (std::memcmp(magic, kMagic, 8) != 0)
    throw RecordingError("recording format " + std::string(magic, 8) +
                         " is not supported: this plcrun reads " + std::string(kMagic, 8) +
                         " (record the cell again)");
  std::uint8_t type = 0;
  std::span<const std::uint8_t> payload;
  if (!frame(type, payload)) throw RecordingError("recording incomplete: it has no header");
  if (type != kHeader) damaged("the first record is not the header");
  parse_header(payload);
  tasks_.resize(layout_.tasks.size());
}

bool RecordingReader::frame(std::uint8_t& type, std::span<const std::uint8_t>& payload) {
  record_offset_ = pos_;
  if (pos_ == size_) return false;
  std::uint8_t head[kHead];
  if (!read(head, kHead))
    throw RecordingError("recording incomplete: the file ends inside a record after scan " +
                         std::to_string(scans_) + " (byte offset " +
                         std::to_string(record_offset_) + "): cut off");
  std::uint32_t len = 0;
  std::memcpy(&len, head + 1, 4);
  len = boost::endian::little_to_native(len);
  if (len > kMaxRecordBytes)
    damaged("record length " + std::to_string(len) + " exceeds the limit of " +
            std::to_string(kMaxRecordBytes) + " bytes");
  if (std::uint64_t(len) + kTail > size_ - pos_)
    throw RecordingError("recording incomplete or damaged at scan " + std::to_string(scans_) +
                         " (byte offset " + std::to_string(record_offset_) +
                         "): the record's length (" + std::to_string(len) +
                         " bytes) runs past the end of the file (cut off, or a damaged length)");
  buf_.resize(std::size_t(len) + kTail);
  if (!read(buf_.data(), buf_.size())) damaged("read error");
  crc_.process_bytes(head, kHead);
  crc_.process_bytes(buf_.data(), len);
  std::uint32_t stored = 0;
  std::memcpy(&stored, buf_.data() + len, 4);
  if (boost::endian::little_to_native(stored) != crc_.checksum()) damaged("CRC mismatch");
  type = head[0];
  payload = {buf_.data(), len};
  ++records_;
  return true;
}

void RecordingReader::parse_header(std::span<const std::uint8_t> p) {
  In in(p);
  std::uint16_t ntasks = 0;
  if (!in.le(layout_.layout_hash)) damaged("header too short");
  for (std::uint32_t& s : layout_.image_bytes)
    if (!in.le(s) || s > kMaxImageBytes) damaged("header: bad image size");
  if (!in.le(layout_.devices) || !in.le(ntasks) || ntasks == 0) damaged("header: bad counts");
  for (std::uint16_t i = 0; i < ntasks; ++i) {
    RecordingLayout::Task t;
    if (!in.le(t.period_ns) || !in.le(t.input_bytes) || !in.le(t.programs))
      damaged("header too short");
    if (t.period_ns <= 0 || t.period_ns > kMaxTimeNs) damaged("header: bad task period");
    if (t.input_bytes > layout_.image_bytes[0]) damaged("header: task inputs exceed %I");
    layout_.tasks.push_back(t);
  }
  if (in.left()) damaged("header: trailing bytes");
}

bool RecordingReader::next(Record& r) {
  std::uint8_t type = 0;
  std::span<const std::uint8_t> payload;
  if (!frame(type, payload)) {
    if (ended_) return false;
    throw RecordingError("recording incomplete: it ends after scan " + std::to_string(scans_) +
                         " without its end record (cut off, or the recorder could not finish)");
  }
  if (ended_) damaged("data after the end record");
  r = Record{};
  r.type = static_cast<Type>(type);
  r.offset = record_offset_;
  r.scan = scans_;
  In in(payload);
  switch (type) {
    case kLatch:
      parse_latch(in, r);
      break;
    case kMerge:
      parse_merge(in, r);
      break;
    case kStop:
      parse_stop(in, r);
      break;
    case kChange:
      parse_change(in, r);
      break;
    case kEnd:
      parse_end(in);
      break;
    default:
      damaged("unknown record type " + std::to_string(type));
  }
  if (in.left()) damaged("trailing bytes in the record");
  if (type == kEnd) {
    if (pos_ != size_) damaged("data after the end record");
    return false;
  }
  return true;
}

void RecordingReader::parse_latch(In& in, Record& r) {
  if (!in.le(r.task) || r.task >= tasks_.size()) damaged("latch of an unknown task");
  TaskState& ts = tasks_[r.task];
  const RecordingLayout::Task& lt = layout_.tasks[r.task];
  if (ts.stopped) damaged("latch of a stopped task");
  if (ts.open) damaged("latch of a task whose previous scan has not merged");
  if (!in.le(r.cycle) || !in.le(r.time_ns)) damaged("latch too short");
  if (r.time_ns < 0 || r.time_ns > kMaxTimeNs)
    damaged("time " + std::to_string(r.time_ns) + " ns out of range");
  if (r.time_ns % lt.period_ns != 0) damaged("time off the task's period grid");
  if (ts.seen && (r.time_ns <= ts.time_ns || r.cycle != ts.cycle + 1))
    damaged("time or cycle not after the task's previous scan");
  std::uint16_t ndev = 0;
  if (!in.take(lt.input_bytes, r.inputs) || !in.le(ndev)) damaged("latch too short");
  if (ndev != layout_.devices) damaged("device count differs from the header");
  if (!in.take(ndev, r.states)) damaged("latch too short");
  for (std::uint8_t s : r.states)
    if (s > kMaxDeviceState) damaged("device state " + std::to_string(s) + " out of range");
  if (!in.le(r.answer_count)) damaged("latch too short");
  const std::size_t answers_at = in.pos();
  for (std::uint16_t k = 0; k < r.answer_count; ++k) {
    std::uint16_t dev = 0, err = 0, len = 0;
    std::uint32_t seq = 0;
    std::uint8_t status = 0;
    std::span<const std::uint8_t> data;
    if (!in.le(dev) || !in.le(seq) || !in.le(status) || !in.le(err) || !in.le(len))
      damaged("answer too short");
    if (dev >= ndev) damaged("answer of an unknown device");
    if (status != static_cast<std::uint8_t>(io::RecordStatus::Done) &&
        status != static_cast<std::uint8_t>(io::RecordStatus::Error))
      damaged("answer status out of range");
    if (len > io::kRecordMaxBytes || !in.take(len, data)) damaged("answer length out of range");
  }
  r.answers = in.since(answers_at);
  check_events(in, r, true, r.event_groups, r.events);
  std::uint8_t snap = 0;
  if (!in.le(snap) || snap > 1) damaged("bad snapshot flag");
  if ((snap == 1) != !had_latch_)
    damaged(snap ? "a second snapshot" : "the first latch has no snapshot");
  if (snap) {
    const std::size_t at = in.pos();
    check_snapshot(in);
    r.snapshot = in.since(at);
  }
  had_latch_ = true;
  ts.open = ts.seen = true;
  ts.cycle = r.cycle;
  ts.time_ns = r.time_ns;
}

// Event groups: u16 count; per group u8 point, u16 program index, u16
// events; per event u8 target and then
//   images:   u8 area, u32 byte, u8 bit, u8 type, u8 byte order, value
//   variable: u16 path length, path, u8 type, value.
void RecordingReader::check_events(In& in, const Record& r, bool latch, std::uint16_t& groups,
                                   std::span<const std::uint8_t>& out) {
  if (!in.le(groups)) damaged("events too short");
  const std::size_t at = in.pos();
  int last = -1;
  for (std::uint16_t g = 0; g < groups; ++g) {
    std::uint8_t point = 0;
    std::uint16_t index = 0, n = 0;
    if (!in.le(point) || !in.le(index) || !in.le(n)) damaged("events too short");
    if (latch ? point != kAfterLatch : (point < kBeforePrograms || point > kBeforePublish))
      damaged("event point out of range");
    if (point == kBeforeProgram ? index >= layout_.tasks[r.task].programs : index != 0)
      damaged("event program index out of range");
    const int order = point * 65536 + index;
    if (order <= last) damaged("event groups out of order");
    last = order;
    for (std::uint16_t k = 0; k < n; ++k) {
      std::uint8_t target = 0, type = 0;
      if (!in.le(target) || target > kVariable) damaged("event target out of range");
      if (target == kVariable) {
        std::uint16_t len = 0;
        std::span<const std::uint8_t> path;
        if (!in.le(len) || len == 0 || len > kMaxPathBytes || !in.take(len, path) || !in.le(type) ||
            !skip_value(in, type))
          damaged("bad variable event");
        continue;
      }
      std::uint8_t area = 0, bit = 0, order_byte = 0;
      std::uint32_t byte = 0;
      if (!in.le(area) || !in.le(byte) || !in.le(bit) || !in.le(type) || !in.le(order_byte))
        damaged("image event too short");
      if (area > 2 || bit > 7 || order_byte > 1 ||
          type >= static_cast<std::uint8_t>(VarType::STRING))
        damaged("image event out of range");
      const std::size_t width = size_of(static_cast<VarType>(type));
      if (std::uint64_t(byte) + width > layout_.image_bytes[area])
        damaged("image event outside the image");
      if (!skip_value(in, type)) damaged("bad image event value");
    }
  }
  out = in.since(at);
}

// Snapshot: u32 variables; per variable u16 path length, path, u8 type,
// value; then %I, %Q, %M of the global image, each u32 size and bytes;
// then per device the u32 number of its last acyclic request.
void RecordingReader::check_snapshot(In& in) {
  std::uint32_t nvars = 0;
  if (!in.le(nvars) || nvars > in.left()) damaged("bad snapshot");
  for (std::uint32_t i = 0; i < nvars; ++i) {
    std::uint16_t len = 0;
    std::uint8_t type = 0;
    std::span<const std::uint8_t> path;
    if (!in.le(len) || len == 0 || len > kMaxPathBytes || !in.take(len, path) || !in.le(type) ||
        !skip_value(in, type))
      damaged("bad snapshot variable");
  }
  for (std::uint32_t expected : layout_.image_bytes) {
    std::uint32_t n = 0;
    std::span<const std::uint8_t> bytes;
    if (!in.le(n) || n != expected || !in.take(n, bytes)) damaged("bad snapshot image");
  }
  for (std::uint16_t d = 0; d < layout_.devices; ++d) {
    std::uint32_t seq = 0;
    if (!in.le(seq)) damaged("bad snapshot request number");
  }
}

void RecordingReader::parse_merge(In& in, Record& r) {
  if (!in.le(r.task) || r.task >= tasks_.size()) damaged("merge of an unknown task");
  if (!tasks_[r.task].open) damaged("merge of a task without its latch");
  check_events(in, r, false, r.event_groups, r.events);
  if (!in.le(r.hash)) damaged("merge too short");
  tasks_[r.task].open = false;
  ++scans_;
}

void RecordingReader::parse_stop(In& in, Record& r) {
  std::uint16_t len = 0;
  std::span<const std::uint8_t> text;
  if (!in.le(r.task) || r.task >= tasks_.size()) damaged("stop of an unknown task");
  if (tasks_[r.task].stopped) damaged("a task stopped twice");
  if (!in.le(len) || len > kMaxPathBytes || !in.take(len, text)) damaged("bad stop record");
  r.reason = {reinterpret_cast<const char*>(text.data()), text.size()};
  tasks_[r.task].stopped = true;
  tasks_[r.task].open = false;
}

// A change record: the start builds before the first latch (task kNoTask,
// number 0); a change's records between the scans of the tasks concerned,
// numbered 1, 2, ... in order, one per task and change.
void RecordingReader::parse_change(In& in, Record& r) {
  std::uint16_t len = 0;
  std::uint32_t report_len = 0;
  std::span<const std::uint8_t> path, report;
  if (!in.le(r.task) || !in.le(r.change) || !in.le(len) || len == 0 || len > kMaxPathBytes ||
      !in.take(len, path) || !in.le(r.crc32) || !in.le(r.size) || !in.le(report_len) ||
      report_len > kMaxReportBytes || !in.take(report_len, report))
    damaged("bad change record");
  r.library = {reinterpret_cast<const char*>(path.data()), path.size()};
  r.report = {reinterpret_cast<const char*>(report.data()), report.size()};
  if (r.task == kNoTask) {
    if (had_latch_ || r.change != 0) damaged("a start build after the first latch");
    return;
  }
  if (r.task >= tasks_.size()) damaged("change of an unknown task");
  if (!had_latch_) damaged("a change before the first latch");
  TaskState& ts = tasks_[r.task];
  if (ts.open || ts.stopped) damaged("a change inside a scan or of a stopped task");
  if (r.change == 0 || r.change < last_change_ || r.change > last_change_ + 1 ||
      r.change <= ts.change)
    damaged("change number " + std::to_string(r.change) + " out of order");
  last_change_ = r.change;
  ts.change = r.change;
}

void RecordingReader::parse_end(In& in) {
  std::uint64_t scans = 0, records = 0;
  if (!in.le(scans) || !in.le(records)) damaged("end record too short");
  if (scans != scans_)
    damaged("the end record counts " + std::to_string(scans) + " scans, the file has " +
            std::to_string(scans_));
  if (records != records_ - 1)
    damaged("the end record counts " + std::to_string(records) + " records, the file has " +
            std::to_string(records_ - 1));
  ended_ = true;
}

namespace {

RecordingCheck check(RecordingReader& r) {
  RecordingCheck c;
  Record rec;
  while (r.next(rec)) {
  }
  c.ok = true;
  c.scans = r.scans();
  return c;
}

}  // namespace

RecordingCheck check_recording(std::span<const std::uint8_t> bytes) {
  try {
    RecordingReader r(bytes);
    return check(r);
  } catch (const std::exception& e) {
    return {false, e.what(), 0};
  }
}

RecordingCheck check_recording_file(const std::string& path) {
  try {
    RecordingReader r(path);
    return check(r);
  } catch (const std::exception& e) {
    return {false, e.what(), 0};
  }
}

}  // namespace plc::debug

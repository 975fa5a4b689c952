// Record every plugin input per scan, and replay a recording in virtual time
// with bit-identical outputs: a bug met on a test bench can be stepped
// through at a desk.
//
// What a recording holds, so that the replay is exact:
// * per scan, its time and cycle count (the scan's ScanContext), the inputs
//   of the task's devices as the programs saw them (forced inputs
//   included), every device's communication state, and the answers to
//   acyclic requests that this scan is the first to see (the Runtime makes
//   both change only at a task's latch, in real time as in virtual time);
// * the ORDER of the image-locked halves of the scans: in real time the
//   tasks run concurrently, and what task B's latch copies of %Q/%M depends
//   on whether task A merged before it. Each scan is two records, a latch
//   (written under the image lock at step 1) and a merge (written under the
//   image lock at step 5), so the file order is the order in which the
//   tasks' locked sections really ran, and the replayer runs the two halves
//   apart in that order (Runtime::latch_scan / finish_scan);
// * every write the debugger made during the scan (write, force, unforce
//   restore, writes at freeze points), with the point of the scan where it
//   was made, and tasks stopped by their watchdog or a fault (the safe
//   outputs that go into the image then);
// * at its first scan, a snapshot of the state the programs had then: every
//   reflected program variable, the global image, and each device's
//   acyclic request numbering. A recording can start in the middle of a
//   session; it starts at the first latch at which no other task is inside
//   a scan (real time) and no acyclic request is on its way or answered
//   (a request object is not reflected state), so that the snapshot is
//   consistent. State a program does not reflect is not in the snapshot
//   (reflect all of it: the debugger needs it too).
//
// The replayer runs the records in file order against the same cell
// without its devices and compares, at every merge, a hash of the global
// %Q and %M with the recorded one; the first difference is reported with
// its scan number.
//
// Online change (plc/online_change.hpp) during a recording: a change record
// notes, per cell library, the build in use at the start (after the
// header), and for every change, per task concerned, the build it switched
// to, right before that task's first latch with the new code, with the
// change's report. The recorder keeps a copy of every build it notes beside
// the recording (FILE.libs/NAME.CRC8HEX), since a rebuild replaces the file
// at the library's path. The replayer runs each build again: from the
// library's path if the file there is that build (same CRC-32 and size),
// else from the kept copy; if neither is, the replay is refused before its
// first scan, naming the file and both CRCs.
//
// File format PLCREC05, all integers little-endian:
//   "PLCREC05", then records: u8 type, u32 payload length, payload, u32 CRC.
//   CRC: CRC-32 (IEEE 802.3, zlib's crc32) over the type, length and payload
//   of every record from the first up to this one (a running CRC, so a lost,
//   repeated or reordered record is caught as well as a flipped bit).
//   H header  u64 layout hash, u32 image sizes %I %Q %M, u16 devices,
//             u16 tasks, per task i64 period ns, u32 input bytes, u16 programs
//   L latch   u16 task, u64 cycle, i64 time ns, the task's input bytes,
//             u16 devices + u8 state each, u16 answers + per answer u16
//             device, u32 request seq, u8 status, u16 error, u16 length,
//             data, debugger writes (recording_reader.cpp), u8 1 + snapshot
//             in the first latch, else u8 0; snapshot: u32 variables + per
//             variable u16 path length, path, u8 type, value; %I %Q %M each
//             u32 size + bytes; per device u32 last request number
//   M merge   u16 task, debugger writes, u64 hash of global %Q and %M
//   T stop    u16 task, u16 length + reason
//   C change  u16 task (0xFFFF: the build at the start, before the first
//             latch), u32 change number (0 at the start, then 1, 2, ...),
//             u16 length + library path, u32 CRC-32 and u64 size of the
//             build's bytes, u32 length + the change's report text
//   E end     u64 scans (merge records), u64 records before it; the last
//             bytes of the file
// A file without its end record is incomplete (cut off, or the recorder
// could not finish it); RecordingReader checks all of it.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "plc/debug/recording_format.hpp"
#include "plc/debug/recording_reader.hpp"
#include "plc/runtime.hpp"

namespace plc {
class CellLibrary;
class OnlineChange;
}  // namespace plc

namespace plc::debug {

// Where a recording keeps its copy of a library build (see above).
std::string library_copy_path(const std::string& recording, const std::string& library,
                              std::uint32_t crc32);
// The file holding that build: `library` itself if it is that build, else
// the kept copy; throws RecordingError naming both when neither is.
std::string find_library_build(const std::string& recording, const std::string& library,
                               std::uint32_t crc32, std::uint64_t size);

class RecordingWriter;
class ImageMirror;

// Scan threads only copy bytes into preallocated buffers (no allocation,
// no I/O); a writer thread writes the file, and computes the merge records'
// output hashes from the image deltas the scans hand it (image_mirror.hpp:
// the scan compares %Q and %M with its copy instead of hashing them, and
// only the words it can have changed: its task's bound bytes, the words
// the debugger wrote since the last comparison; the whole of them at the
// start, after an online change, a stopped task's safe outputs, a scan
// merged unrecorded, or more than kMarks writes). Real time: several task
// threads record at once; the latch and merge records are written under
// the image lock the scan holds anyway, the rest of a scan's record goes
// into the task's own buffer.
class Recorder final : public ScanHooks {
 public:
  // Self: the recorder adds itself to the runtime's hooks (before the
  // runtime starts). ByCaller: the caller forwards the hooks after its own
  // (the debugger, which may start and stop a recording while real-time
  // tasks run) and calls arm() when it starts forwarding.
  enum class Attach { Self, ByCaller };
  // Throws std::runtime_error if the file cannot be written.
  Recorder(Runtime& rt, const std::string& file, Attach attach = Attach::Self);
  ~Recorder() override;
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Notes which tasks are inside a scan now: the recording starts at a
  // latch when no other task is.
  void arm();

  // The recorder writes no image byte and reads only the global image (the
  // latched inputs, the merged %Q/%M, the snapshot): the scans it records
  // copy and merge only their bound bytes, as they do without it, so a
  // recording costs no whole-image copy and records the scans as they run
  // unrecorded. (The debugger, whose writes and forces reach any byte,
  // keeps the whole-image scans while it is attached.)
  [[nodiscard]] bool whole_image() const override { return false; }

  void after_latch(TaskRuntime& t, io::ProcessImage& global) override;
  void on_answer(TaskRuntime& t, std::size_t device, const io::RecordRequest& r) override;
  void before_programs(TaskRuntime& t, const ScanContext& ctx) override;
  void before_program(TaskRuntime& t, std::size_t index, const ScanContext& ctx) override;
  void after_programs(TaskRuntime& t, const ScanContext& ctx) override;
  void before_publish(TaskRuntime& t, io::ProcessImage& global) override;
  void on_stop(TaskRuntime& t, io::ProcessImage& global) override;

  // The debugger wrote `value` (native) to `v` in t's scan, at the hook
  // point whose recorder hook comes next for t.
  void note_write(TaskRuntime& t, const VarInfo& v, const void* value);

  // An online change, prepared and not yet committed: each task concerned
  // gets its change record at its next latch (where the swap applies).
  // Keeps a copy of the new build. "" or why the recording cannot note it
  // (it has not started yet: its snapshot would be of the new build).
  std::string note_change(const OnlineChange& change, const std::string& report);
  [[nodiscard]] bool started() const { return active_; }

  // Ends the recording (end record, file closed); "" or what went wrong
  // (a write error, a full disk, lost records): then the file is not a
  // complete recording.
  std::string close();
  [[nodiscard]] std::uint64_t scans() const { return scans_.load(std::memory_order_relaxed); }
  [[nodiscard]] bool failed() const { return dead_.load(std::memory_order_acquire); }

 private:
  // The words of %Q and %M a diff covers: a task's bound bytes, and the
  // words the debugger wrote (at most kMarks between two diffs; more make
  // the next diffs whole).
  using Words = recfmt::ImageWords;
  static constexpr std::size_t kMarks = 64;
  struct Marks {
    std::array<Words, kMarks> w{};
    std::size_t n = 0;
  };
  struct TaskRec {
    enum State : std::uint8_t { Idle, Open, Busy };  // Busy: in a scan not recorded
    State state = Idle;
    std::vector<Words> bound;      // the words its merge can change
    Marks marks;                   // written into its private image since its last diff
    std::uint64_t whole_seen = 0;  // whole_epoch_ at its last whole diff
    std::size_t input_bytes = 0;   // its devices' inputs, in its latch record
    recfmt::Buf merge;             // the merge record being built
    std::uint16_t merge_groups = 0;
    recfmt::Buf pending;  // debugger writes not yet given their hook point
    std::uint16_t pending_count = 0;
    recfmt::Buf change;  // a change record due at the next latch
    std::atomic<bool> change_due{false};
  };
  void put_change(recfmt::Buf& b, std::uint16_t task, std::uint32_t number, const CellLibrary& lib,
                  const std::string& report);
  void keep_copy(const CellLibrary& lib);
  void commit(const recfmt::Buf& b, bool wait);
  void fail(const std::string& why);
  bool try_start(const TaskRuntime& t);
  void put_snapshot(recfmt::Buf& b);
  void seal(TaskRec& ts, recfmt::Point point, std::size_t index);
  void mark(Marks& m, bool output, std::size_t byte, std::size_t n);
  // The next diff of every task compares the whole %Q and %M: what wrote
  // them since is not known word by word (the start, an online change, a
  // stop's safe outputs, a scan merged unrecorded, too many marks).
  void diff_whole_next() { whole_epoch_.fetch_add(1, std::memory_order_relaxed); }
  std::size_t snapshot_bytes() const;

  Runtime& rt_;
  std::string file_;
  bool attached_;
  std::unique_ptr<RecordingWriter> writer_;
  std::vector<TaskRec> tasks_;
  // Used under the image lock only (one task at a time): the latch, stop
  // and end records, the answers collected during a latch, the image
  // deltas and the copy of %Q and %M they are taken against.
  recfmt::Buf shared_, answers_, delta_;
  std::unique_ptr<ImageMirror> mirror_;
  Marks marks_;  // words of the global image the debugger wrote since the last diff
  std::atomic<std::uint64_t> whole_epoch_{1};
  std::uint16_t answer_count_ = 0;
  bool active_ = false;  // the first latch (with the snapshot) is written
  std::uint64_t records_ = 0;
  std::uint32_t changes_ = 0;
  std::atomic<std::uint64_t> scans_{0};
  std::atomic<bool> dead_{false};  // failed: nothing more is recorded
  std::mutex error_mu_;
  std::string error_;
  bool closed_ = false;
};

class Replayer final : public ScanHooks {
 public:
  // Reads the whole recording first and checks it (RecordingReader), so a
  // damaged file is refused before the first scan. Throws
  // std::runtime_error if the file cannot be opened, RecordingError if it
  // is damaged, incomplete, of another version, or of another cell layout.
  Replayer(Runtime& rt, const std::string& file);
  ~Replayer() override;

  // Runs the next recorded scan (its latch, what the other tasks did in
  // between, its merge); false at the end of the recording or on an error.
  bool step();
  [[nodiscard]] std::uint64_t scans() const { return scans_; }
  [[nodiscard]] std::uint64_t total_scans() const { return total_scans_; }
  [[nodiscard]] std::uint64_t mismatches() const { return mismatches_; }
  [[nodiscard]] std::int64_t first_mismatch() const { return first_mismatch_; }  // -1 = none
  [[nodiscard]] bool at_end() const { return end_; }
  [[nodiscard]] const std::string& error() const { return error_; }

  void after_latch(TaskRuntime& t, io::ProcessImage& global) override;
  void before_programs(TaskRuntime& t, const ScanContext& ctx) override;
  void before_program(TaskRuntime& t, std::size_t index, const ScanContext& ctx) override;
  void after_programs(TaskRuntime& t, const ScanContext& ctx) override;
  void before_publish(TaskRuntime& t, io::ProcessImage& global) override;

 private:
  // The builds the recording ran (change number -> the file to load).
  struct Build {
    std::uint32_t number = 0;
    std::string library, file;
  };
  void switch_build(const Build& b, bool now);
  void restore_snapshot(std::span<const std::uint8_t> s);
  void apply_events(TaskRuntime& t, recfmt::Point point, std::size_t index);
  void diverged(const std::string& what);

  Runtime& rt_;
  std::unique_ptr<RecordingReader> reader_;
  Record rec_;                        // the record being replayed
  std::vector<ScanContext> pending_;  // per task: its latched scan
  std::vector<Build> builds_;
  std::unique_ptr<OnlineChange> change_;  // committed, not all tasks switched yet
  std::uint32_t change_number_ = 0;
  std::uint64_t scans_ = 0, total_scans_ = 0, mismatches_ = 0;
  std::int64_t first_mismatch_ = -1;
  bool end_ = false;
  std::string error_;
};

}  // namespace plc::debug

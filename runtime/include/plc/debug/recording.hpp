// Record every plugin input per scan, and replay a recording in virtual time
// with bit-identical outputs: a bug met on a test bench can be stepped
// through at a desk.
//
// A recording may start in the middle of a session: its first scan carries
// a snapshot of the state the programs had then (every reflected program
// variable, the images, the task cycle counters), taken after the inputs
// were latched and the debugger's writes applied, and restored at the same
// point of the replay's first scan. State that a program does not reflect is
// not in the snapshot (reflect all of it: the debugger needs it too), and
// forces on outputs or program variables made while recording are not
// recorded (forced inputs are: they are what the programs saw).
//
// Besides the cyclic inputs, a scan's inputs include what the plugins
// answered to acyclic requests (record read/write) and each device's
// communication state: both are recorded in the scan that first sees them
// and given back at the same point of the replay. The Runtime makes both
// change only at a task's latch (DeviceLink deferred delivery), so this
// holds in real time as in virtual time: no answer appears mid-scan.
//
// File format (host byte order; written and read on the same architecture):
//   header  "PLCREC03", u64 layout hash (Runtime::layout_hash)
//   per scan: u8 tag 'S', u16 task index, i64 time ns,
//             the task's devices' input bytes (in config order, sizes from
//             the layout),
//             u8 device count, u8 state of every device (config order),
//             u16 answer count, per answer: u16 device, u32 request seq,
//               u8 status, u16 error, u16 length, data,
//             u8 1 + snapshot (first scan) or u8 0,
//             u64 FNV-1a hash of those devices' published output bytes.
// The replayer runs the scans in the recorded order at the recorded times,
// feeds the recorded inputs instead of the plugins', and compares each
// scan's output hash: the first divergence is reported with its scan number.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "plc/runtime.hpp"

namespace plc::debug {

std::uint64_t fnv1a(const std::uint8_t* p, std::size_t n, std::uint64_t h = 1469598103934665603ULL);

class Recorder final : public ScanHooks {
 public:
  // Throws std::runtime_error if the file cannot be written.
  Recorder(Runtime& rt, const std::string& file);
  ~Recorder() override;
  void after_latch(TaskRuntime& t, io::ProcessImage& global) override;
  void on_answer(TaskRuntime& t, std::size_t device, const io::RecordRequest& r) override;
  void before_programs(TaskRuntime& t, const ScanContext& ctx) override;
  void before_publish(TaskRuntime& t, io::ProcessImage& global) override;
  void close();
  [[nodiscard]] std::uint64_t scans() const { return scans_; }

 private:
  void flush();
  Runtime& rt_;
  std::FILE* f_ = nullptr;
  std::vector<std::uint8_t> buf_, answers_;
  std::uint16_t answer_count_ = 0;
  std::uint64_t scans_ = 0;
};

class Replayer final : public ScanHooks {
 public:
  // Throws std::runtime_error for a missing file, a bad header, or a
  // recording made on a different cell layout.
  Replayer(Runtime& rt, const std::string& file);
  ~Replayer() override;

  // Runs the next recorded scan; false at the end of the recording.
  bool step();
  [[nodiscard]] std::uint64_t scans() const { return scans_; }
  [[nodiscard]] std::uint64_t mismatches() const { return mismatches_; }
  [[nodiscard]] std::int64_t first_mismatch() const { return first_mismatch_; }  // -1 = none
  [[nodiscard]] bool at_end() const { return end_; }
  [[nodiscard]] const std::string& error() const { return error_; }

  void after_latch(TaskRuntime& t, io::ProcessImage& global) override;
  void before_programs(TaskRuntime& t, const ScanContext& ctx) override;
  void before_publish(TaskRuntime& t, io::ProcessImage& global) override;

 private:
  bool read_snapshot();
  bool read_states_and_answers();
  Runtime& rt_;
  std::FILE* f_ = nullptr;
  std::vector<std::uint8_t> inputs_;
  std::vector<std::uint8_t> states_;
  std::vector<std::uint8_t> answers_;   // this scan's answers, as recorded
  std::vector<std::uint8_t> snapshot_;  // pending restore (first scan)
  std::uint64_t expected_hash_ = 0;
  std::uint64_t scans_ = 0, mismatches_ = 0;
  std::int64_t first_mismatch_ = -1;
  bool end_ = false;
  std::string error_;
};

}  // namespace plc::debug

// Reading a recording (format: recording.hpp) with every check made before a
// byte of it is used: the running CRC of each record, every length against
// the bytes left in the file (before anything is allocated), every count,
// index, time and state against the header's layout, the order of the
// records (a latch before its merge, one task scan at a time, times rising
// on the task's period grid, cycles counting up by one), and the end record
// (scan and record counts) as the last bytes of the file.
//
// Any damage throws RecordingError naming the scan and the byte offset:
//   "recording damaged at scan 1234 (byte offset 56789): CRC mismatch"
// and a file without its end record is "incomplete". The reader needs no
// Runtime: the header carries the layout it checks against, so a file can
// be verified on its own (check_recording(), e.g. from a fuzz target); the
// replayer also compares that layout with the cell's.
#pragma once

#include <cstdint>
#include <cstdio>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "plc/debug/recording_format.hpp"

namespace plc {
class Runtime;
}

namespace plc::debug {

// A recording that cannot be replayed because of its content (damaged,
// incomplete, another version, another cell). plcrun exits with 1.
class RecordingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What a recording's header says about the cell it was made on.
struct RecordingLayout {
  struct Task {
    std::int64_t period_ns = 0;
    std::uint32_t input_bytes = 0;  // of the devices it exchanges
    std::uint16_t programs = 0;
    friend bool operator==(const Task&, const Task&) = default;
  };
  std::uint64_t layout_hash = 0;   // Runtime::layout_hash
  std::uint32_t image_bytes[3]{};  // %I, %Q, %M
  std::uint16_t devices = 0;
  std::vector<Task> tasks;

  static RecordingLayout of(Runtime& rt);
  friend bool operator==(const RecordingLayout&, const RecordingLayout&) = default;
};

// One checked record; the views point into the reader's buffer and stay
// valid until the next call of next().
struct Record {
  recfmt::Type type = recfmt::kEnd;
  std::uint64_t offset = 0;  // byte offset of the record in the file
  std::uint64_t scan = 0;    // merge records (whole scans) before it
  std::uint16_t task = 0;    // latch, merge, stop
  // Latch: the scan's cycle count and time, its devices' inputs, every
  // device's state, the acyclic answers, the debugger's writes (event
  // groups) and, in the first latch, the snapshot.
  std::uint64_t cycle = 0;
  std::int64_t time_ns = 0;
  std::span<const std::uint8_t> inputs, states, answers, snapshot;
  std::uint16_t answer_count = 0;
  // Latch and merge: the debugger's writes.
  std::span<const std::uint8_t> events;
  std::uint16_t event_groups = 0;
  // Merge: the hash of the global %Q and %M after the merge.
  std::uint64_t hash = 0;
  // Stop: why the task stopped.
  std::string_view reason;
  // Change: its number, the library, the build (CRC-32, size), the report.
  std::uint32_t change = 0;
  std::string_view library, report;
  std::uint32_t crc32 = 0;
  std::uint64_t size = 0;
};

class RecordingReader {
 public:
  // Throws std::runtime_error if the file cannot be opened, RecordingError
  // if it is not a PLCREC05 recording.
  explicit RecordingReader(const std::string& path);
  explicit RecordingReader(std::span<const std::uint8_t> bytes);
  ~RecordingReader();
  RecordingReader(const RecordingReader&) = delete;
  RecordingReader& operator=(const RecordingReader&) = delete;

  [[nodiscard]] const RecordingLayout& layout() const { return layout_; }
  // The next record (latch, merge, stop or change), checked; false after the end
  // record. Throws RecordingError for any damage.
  bool next(Record& r);
  [[nodiscard]] std::uint64_t scans() const { return scans_; }

 private:
  void open();
  bool read(void* dst, std::size_t n);
  // Reads and CRC-checks one record into buf_; false at the end of the file.
  bool frame(std::uint8_t& type, std::span<const std::uint8_t>& payload);
  void parse_header(std::span<const std::uint8_t> p);
  void parse_latch(recfmt::In& in, Record& r);
  void parse_merge(recfmt::In& in, Record& r);
  void parse_stop(recfmt::In& in, Record& r);
  void parse_change(recfmt::In& in, Record& r);
  void parse_end(recfmt::In& in);
  void check_events(recfmt::In& in, const Record& r, bool latch, std::uint16_t& groups,
                    std::span<const std::uint8_t>& out);
  void check_snapshot(recfmt::In& in);
  [[noreturn]] void damaged(const std::string& what) const;

  std::FILE* f_ = nullptr;
  std::span<const std::uint8_t> mem_;
  std::uint64_t size_ = 0, pos_ = 0;
  std::vector<std::uint8_t> buf_;
  recfmt::RunningCrc crc_;
  RecordingLayout layout_;
  std::uint64_t record_offset_ = 0, records_ = 0, scans_ = 0;
  std::uint32_t last_change_ = 0;
  bool ended_ = false, had_latch_ = false;
  struct TaskState {
    bool open = false, stopped = false, seen = false;
    std::uint32_t change = 0;  // the last change it switched to
    std::uint64_t cycle = 0;
    std::int64_t time_ns = 0;
  };
  std::vector<TaskState> tasks_;
};

// Reads a whole recording and reports the first damage (fuzz targets,
// tools): ok, or the error RecordingReader would throw.
struct RecordingCheck {
  bool ok = false;
  std::string error;
  std::uint64_t scans = 0;
};
RecordingCheck check_recording(std::span<const std::uint8_t> bytes);
RecordingCheck check_recording_file(const std::string& path);

}  // namespace plc::debug

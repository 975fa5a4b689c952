// Trace chosen variables once per scan of a sampling task, to CSV or to VCD
// (viewable in GTKWave), with an optional start trigger and a pre-trigger
// ring buffer: the rows before the trigger are kept and written when it
// fires, so the file shows what led up to the event.
//
// Sampling only copies the traced variables' storage bytes into
// preallocated blocks of rows, as a few memcpy of the byte spans they cover
// (worked out at start: an array's traced elements are one span); a writer
// thread converts them to values (byte order, bits), formats full blocks and
// writes them. So the scan thread does no per-variable work at all. When the writer falls more than
// the preallocated blocks behind: in virtual time (backpressure on, the default) the sampling waits
// for it, which costs nothing but wall time; in real time a new block is allocated rather than a
// row lost (counted in overflow_blocks()).
#pragma once

#include <array>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "plc/debug/condition.hpp"
#include "plc/runtime.hpp"

namespace plc::debug {

enum class TraceFormat { Csv, Vcd };

class Trace {
 public:
  Trace(const VarRegistry& vars, io::ProcessImage& global, io::ByteOrder order)
      : vars_(vars), global_(global), order_(order) {}
  ~Trace() { stop(); }
  Trace(const Trace&) = delete;
  Trace& operator=(const Trace&) = delete;

  // Set-up (while not running). Each returns an error message or "".
  std::string add(const std::string& path_or_address);
  void clear() { columns_.clear(); }
  std::string set_trigger(const std::string& condition);  // "" clears it
  // Rows kept from before the trigger, at most kMaxPretriggerRows (the ring
  // of rows x columns values is allocated when the trace starts).
  static constexpr std::size_t kMaxPretriggerRows = 1'000'000;
  void set_pretrigger(std::size_t rows) { pre_rows_ = rows; }
  // Off for real time: never make a scan thread wait for the disk.
  void set_backpressure(bool on) { backpressure_ = on; }
  // Real time (one_task.hpp): add() and set_trigger() refuse a variable of
  // another task than the trace's others; `task_names` name them in the
  // error. The trace is then sampled after the scans of that task.
  void set_one_task(std::vector<std::string> task_names) {
    one_task_names_ = std::move(task_names);
    one_task_ = true;
  }
  // Opens the file and arms the trace. The format follows the extension
  // (.vcd -> VCD, else CSV) unless given.
  std::string start(const std::string& file, std::optional<TraceFormat> format = std::nullopt);
  // Writes what is buffered and closes the file.
  void stop();
  // Why the file is incomplete ("" = it is not): its writer thread failed
  // (plc/thread_guard.hpp). Valid after stop().
  [[nodiscard]] std::string error() const {
    std::lock_guard<std::mutex> lock(mu_);
    return error_;
  }

  // The task whose scans are sampled: the owner of the first variable, or
  // `fallback` (the fastest task) when no variable belongs to a task. With
  // set_one_task(), the trigger's variables count too.
  [[nodiscard]] int sampling_task(int fallback) const;
  // Whether a row or the trigger reads the global image (an address): in
  // real time the sample is then taken under the image lock.
  [[nodiscard]] bool reads_global() const;
  // Called after each scan of the sampling task.
  void sample(const ScanContext& ctx);

  [[nodiscard]] bool running() const { return file_ != nullptr; }
  [[nodiscard]] bool triggered() const { return triggered_; }
  [[nodiscard]] std::uint64_t rows_written() const { return rows_sampled_; }
  [[nodiscard]] std::uint64_t overflow_blocks() const { return overflow_blocks_; }
  [[nodiscard]] std::size_t columns() const { return columns_.size(); }
  [[nodiscard]] std::string describe() const;

 private:
  struct Column {
    VarInfo var;  // for addresses: points into the global image
  };
  struct Row {
    std::int64_t time_ns;
    std::uint64_t cycle;
  };
  static constexpr std::size_t kBlockRows = 256;
  static constexpr std::size_t kBlocks = 8;
  struct Block {
    std::vector<Row> meta;
    std::vector<std::uint8_t> raw;  // kBlockRows rows of row_bytes_
    std::size_t n = 0;
  };
  // Bytes copied by a sample: [src, src + bytes) to offset `at` of the row.
  struct Span {
    const std::uint8_t* src;
    std::size_t bytes;
    std::size_t at;
  };
  void plan_spans();
  void capture(Row* meta, std::uint8_t* raw, const ScanContext& ctx);
  void append(const Row& m, const std::uint8_t* raw);  // into the current block
  void advance();                                      // the current block's row n is written
  void hand_off();                                     // current block -> writer
  std::unique_ptr<Block> new_block() const;
  void writer_loop();
  void format_row(const Row& m, const std::uint8_t* bytes);
  void flush_text();
  void write_header();

  const VarRegistry& vars_;
  io::ProcessImage& global_;
  io::ByteOrder order_;
  std::vector<Column> columns_;
  std::optional<Condition> trigger_;
  std::size_t pre_rows_ = 0;
  TraceFormat format_ = TraceFormat::Csv;
  std::string file_name_;
  std::FILE* file_ = nullptr;
  bool triggered_ = false;
  std::vector<Span> spans_;                // those of 1, 2, 4, 8 bytes, then the others
  std::array<std::size_t, 4> size_end_{};  // where the spans of 1, 2, 4, 8 bytes end
  std::size_t row_bytes_ = 0;
  // Writer thread: per column, its VarInfo with the storage pointer aimed
  // at the column's bytes in the row being formatted (VarRegistry::read
  // converts them), and the row's values.
  std::vector<std::size_t> column_at_;
  std::vector<VarInfo> decode_;
  std::vector<std::uint64_t> values_;
  // Ring of pre_rows_+1 rows: meta and storage bytes.
  std::vector<Row> meta_;
  std::vector<std::uint8_t> raw_;
  std::size_t ring_head_ = 0, ring_count_ = 0;
  std::vector<std::uint64_t> last_;  // VCD: last written values
  bool have_last_ = false;
  std::string text_;  // writer thread only (and the header before it starts)
  std::uint64_t rows_sampled_ = 0, overflow_blocks_ = 0;
  std::unique_ptr<Block> cur_;
  std::vector<std::unique_ptr<Block>> free_;
  std::deque<std::unique_ptr<Block>> full_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::thread writer_;
  bool closing_ = false;
  std::string error_;  // under mu_: why the writer thread failed
  bool backpressure_ = true;
  bool one_task_ = false;
  std::vector<std::string> one_task_names_;
  // The variables of the columns and the trigger, plus `extra`, must belong
  // to one task (set_one_task); "" or why not.
  [[nodiscard]] std::string one_task_check(const std::vector<const VarInfo*>& extra,
                                           bool with_trigger) const;
};

}  // namespace plc::debug

// Writes a recording on its own thread, so that a scan never waits on the
// disk: the scans copy whole records into preallocated blocks (append());
// this thread fills in each record's running CRC and writes full blocks to
// the file. A write error (a full disk) is kept, further records are
// dropped, and finish() reports it. In real time a scan that finds no free
// block (the disk fell behind by all of them) loses its record and the
// recording is marked broken rather than make the scan wait; in virtual time
// (`wait`) the scan waits for a block, as the trace writer does, so a
// virtual-time recording is always complete.
//
// With an ImageMirror, the writer also fills in the merge records' output
// hash from the image-delta records before them (image_mirror.hpp), and
// leaves the delta records out of the file.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "image_mirror.hpp"
#include "plc/debug/recording_format.hpp"
#include "plc/detail/small_copy.hpp"

namespace plc::debug {

class RecordingWriter {
 public:
  // Takes `fd` (open for writing) and writes `prefix` (the magic) first;
  // `file` names it in errors; `mirror` (may be null): see above.
  RecordingWriter(int fd, std::string file, std::string prefix, std::size_t block_bytes,
                  std::size_t blocks, std::unique_ptr<ImageMirror> mirror = nullptr);
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;

  // One framed record (type, length, payload, CRC slot), at most
  // block_bytes long. One caller at a time. false: the record is lost and
  // the recording broken (error() says why).
  bool append(std::span<const std::uint8_t> record, bool wait) {
    // Nearly every record fits the block being filled: a copy, inline.
    if (cur_ && record.size() <= cur_->data.size() - cur_->n && !failed()) [[likely]] {
      ::plc::detail::copy_bytes(cur_->data.data() + cur_->n, record.data(), record.size());
      cur_->n += record.size();
      return true;
    }
    return append_to_next_block(record, wait);
  }
  // Writes what is left and closes the file; "" or the first error.
  std::string finish();
  [[nodiscard]] bool failed() const { return failed_.load(std::memory_order_acquire); }
  [[nodiscard]] std::string error() const;

 private:
  struct Block {
    std::vector<std::uint8_t> data;
    std::size_t n = 0;
  };
  bool append_to_next_block(std::span<const std::uint8_t> record, bool wait);
  void run();
  void write_out(Block& b);
  void write_all(const std::uint8_t* p, std::size_t n);
  void fail(const std::string& why);

  int fd_;
  std::string file_;
  std::string prefix_;
  std::size_t block_bytes_;
  std::vector<Block> blocks_;
  // Fixed rings of block indices (no allocation after construction).
  std::vector<std::size_t> free_, full_;
  std::size_t free_head_ = 0, free_n_ = 0, full_head_ = 0, full_n_ = 0;
  Block* cur_ = nullptr;   // being filled by append()
  mutable std::mutex mu_;  // the rings and error_, held for a few instructions
  std::condition_variable work_cv_, free_cv_;
  bool closing_ = false;
  std::atomic<bool> failed_{false};
  std::string error_;
  recfmt::RunningCrc crc_;               // writer thread only
  std::unique_ptr<ImageMirror> mirror_;  // writer thread only
  std::thread thread_;
  bool finished_ = false;
};

}  // namespace plc::debug

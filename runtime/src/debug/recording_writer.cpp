#include "recording_writer.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "plc/thread_guard.hpp"

namespace plc::debug {

RecordingWriter::RecordingWriter(int fd, std::string file, std::string prefix,
                                 std::size_t block_bytes, std::size_t blocks,
                                 std::unique_ptr<ImageMirror> mirror)
    : fd_(fd),
      file_(std::move(file)),
      prefix_(std::move(prefix)),
      block_bytes_(block_bytes),
      blocks_(blocks),
      mirror_(std::move(mirror)) {
  free_.resize(blocks);
  full_.resize(blocks);
  for (std::size_t i = 0; i < blocks; ++i) {
    blocks_[i].data.resize(block_bytes);
    free_[i] = i;
  }
  free_n_ = blocks;
  // A failed thread fails the recording (FAILED at its close, exit code 1);
  // the scans' appends are refused from then on, so nothing waits for it.
  thread_ = std::thread([this] {
    run_guarded(
        "recording writer", [this] { run(); },
        [this](std::string_view what) {
          fail("the writer thread failed: " + std::string(what));
          std::lock_guard<std::mutex> lock(mu_);
          free_cv_.notify_all();  // a scan waiting for a buffer sees the failure
        });
  });
}

RecordingWriter::~RecordingWriter() { finish(); }

std::string RecordingWriter::error() const {
  std::lock_guard<std::mutex> lock(mu_);
  return error_;
}

void RecordingWriter::fail(const std::string& why) {
  std::lock_guard<std::mutex> lock(mu_);
  if (error_.empty()) error_ = why;
  failed_.store(true, std::memory_order_release);
}

// The block being filled is full (or there is none yet): hands it to the
// writer thread and takes a free one.
bool RecordingWriter::append_to_next_block(std::span<const std::uint8_t> record, bool wait) {
  if (failed()) return false;
  if (record.size() > block_bytes_) {
    fail("a record of " + std::to_string(record.size()) + " bytes exceeds the recording's blocks");
    return false;
  }
  if (!cur_ || cur_->n + record.size() > cur_->data.size()) {
    std::unique_lock<std::mutex> lock(mu_);
    if (cur_) {
      full_[(full_head_ + full_n_++) % full_.size()] = std::size_t(cur_ - blocks_.data());
      cur_ = nullptr;
      work_cv_.notify_one();
    }
    if (wait) free_cv_.wait(lock, [this] { return free_n_ > 0 || failed(); });
    if (free_n_ == 0) {
      lock.unlock();
      fail(
          "the disk fell behind the scans: every recording buffer was full, so records were "
          "lost and the recording stops here");
      return false;
    }
    cur_ = &blocks_[free_[free_head_]];
    free_head_ = (free_head_ + 1) % free_.size();
    --free_n_;
    cur_->n = 0;
  }
  std::memcpy(cur_->data.data() + cur_->n, record.data(), record.size());
  cur_->n += record.size();
  return true;
}

void RecordingWriter::run() {
  write_all(reinterpret_cast<const std::uint8_t*>(prefix_.data()), prefix_.size());
  std::unique_lock<std::mutex> lock(mu_);
  for (;;) {
    work_cv_.wait(lock, [this] { return full_n_ > 0 || closing_; });
    if (full_n_ == 0) return;  // closing, all written
    Block& b = blocks_[full_[full_head_]];
    full_head_ = (full_head_ + 1) % full_.size();
    --full_n_;
    lock.unlock();
    write_out(b);
    lock.lock();
    free_[(free_head_ + free_n_++) % free_.size()] = std::size_t(&b - blocks_.data());
    free_cv_.notify_one();
  }
}

// Takes the image deltas into the mirror and out of the block, fills in
// the merge records' hashes and every record's CRC, then writes the block.
void RecordingWriter::write_out(Block& b) {
  if (failed()) return;  // the file is broken already; drop the rest
  std::uint8_t* d = b.data.data();
  std::size_t kept = 0;  // bytes of the block that go to the file, moved to its front
  for (std::size_t p = 0; p + recfmt::kHead <= b.n;) {
    std::uint32_t len = 0;
    std::memcpy(&len, d + p + 1, 4);
    len = boost::endian::little_to_native(len);
    const std::size_t body = recfmt::kHead + len;
    const std::size_t whole = body + recfmt::kTail;
    if (p + whole > b.n) break;  // cannot happen: append() copies whole records
    const std::uint8_t type = d[p];
    if (mirror_ && type == kImageDelta) {
      if (!mirror_->apply(std::span(d + p + recfmt::kHead, len))) {
        fail("a malformed image delta (internal error)");
        return;
      }
      p += whole;
      continue;
    }
    if (mirror_ && type == recfmt::kMerge && len >= 8) {
      const std::uint64_t h = boost::endian::native_to_little(mirror_->hash());
      std::memcpy(d + p + body - 8, &h, 8);
    }
    if (kept != p) std::memmove(d + kept, d + p, whole);
    crc_.process_bytes(d + kept, body);
    const std::uint32_t crc = boost::endian::native_to_little(crc_.checksum());
    std::memcpy(d + kept + body, &crc, 4);
    kept += whole;
    p += whole;
  }
  write_all(d, kept);
}

void RecordingWriter::write_all(const std::uint8_t* p, std::size_t n) {
  for (std::size_t done = 0; done < n && !failed();) {
    const ssize_t w = ::write(fd_, p + done, n - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      fail("cannot write '" + file_ + "': " + std::strerror(w < 0 ? errno : EIO));
      return;
    }
    done += std::size_t(w);
  }
}

std::string RecordingWriter::finish() {
  if (finished_) return error();
  finished_ = true;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (cur_ && cur_->n)
      full_[(full_head_ + full_n_++) % full_.size()] = std::size_t(cur_ - blocks_.data());
    cur_ = nullptr;
    closing_ = true;
  }
  work_cv_.notify_one();
  thread_.join();
  if (::close(fd_) != 0) fail("cannot write '" + file_ + "': " + std::strerror(errno));
  return error();
}

}  // namespace plc::debug

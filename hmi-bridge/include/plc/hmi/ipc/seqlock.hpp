// A block of bytes that one thread of plcrun rewrites now and then
// (statistics, diagnostics, the HMI's outage notes) and the bridge reads
// whole, never torn: a sequence lock in shared memory. The writer makes the
// count odd, writes, makes it even; the reader copies and keeps the copy
// only if the count was even and the same before and after. The bytes move
// as relaxed atomic 64-bit words, so the race the protocol tolerates is no
// data race for the compiler (nor for ThreadSanitizer, when both sides run
// in one process).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace plc::hmi::ipc {

struct SeqHeader {
  std::atomic<std::uint64_t> seq{0};
  std::atomic<std::uint64_t> size{0};  // bytes in use
};
static_assert(std::atomic<std::uint64_t>::is_always_lock_free);

// The block at `base`: a SeqHeader, then `capacity` bytes (a multiple of 8).
class SeqBlock {
 public:
  SeqBlock() = default;
  SeqBlock(unsigned char* base, std::size_t capacity) : base_(base), capacity_(capacity / 8 * 8) {}
  // The writer (one thread): false, nothing written, when `bytes` does not fit.
  bool write(const std::vector<unsigned char>& bytes);
  // The reader: true and `out` when a whole, settled copy was read within
  // `tries` attempts.
  bool read(std::vector<unsigned char>& out, int tries = 64) const;
  [[nodiscard]] std::size_t capacity() const { return capacity_; }
  static constexpr std::size_t kHeader = sizeof(SeqHeader);

 private:
  [[nodiscard]] SeqHeader& header() const { return *reinterpret_cast<SeqHeader*>(base_); }
  [[nodiscard]] std::uint64_t* words() const {
    return reinterpret_cast<std::uint64_t*>(base_ + kHeader);
  }
  unsigned char* base_ = nullptr;
  std::size_t capacity_ = 0;
};

}  // namespace plc::hmi::ipc

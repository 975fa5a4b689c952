#include "plc/hmi/ipc/seqlock.hpp"

#include <algorithm>
#include <cstring>

namespace plc::hmi::ipc {

bool SeqBlock::write(const std::vector<unsigned char>& bytes) {
  if (!base_ || bytes.size() > capacity_) return false;
  SeqHeader& h = header();
  const std::uint64_t s = h.seq.load(std::memory_order_relaxed);
  h.seq.store(s + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  std::uint64_t* w = words();
  for (std::size_t i = 0; i < bytes.size(); i += 8) {
    std::uint64_t word = 0;
    std::memcpy(&word, bytes.data() + i, std::min<std::size_t>(8, bytes.size() - i));
    std::atomic_ref<std::uint64_t>(w[i / 8]).store(word, std::memory_order_relaxed);
  }
  h.size.store(bytes.size(), std::memory_order_relaxed);
  h.seq.store(s + 2, std::memory_order_release);
  return true;
}

bool SeqBlock::read(std::vector<unsigned char>& out, int tries) const {
  if (!base_) return false;
  const SeqHeader& h = header();
  const std::uint64_t* w = words();
  for (int t = 0; t < tries; ++t) {
    const std::uint64_t s1 = h.seq.load(std::memory_order_acquire);
    if (s1 & 1) continue;
    const std::uint64_t size = h.size.load(std::memory_order_relaxed);
    if (size > capacity_) continue;  // torn (or a writer that is not ours)
    out.resize(size);
    for (std::size_t i = 0; i < size; i += 8) {
      // A load only (the reader's mapping may be read-only).
      const std::uint64_t word =
          std::atomic_ref<std::uint64_t>(const_cast<std::uint64_t&>(w[i / 8]))
              .load(std::memory_order_relaxed);
      std::memcpy(out.data() + i, &word, std::min<std::size_t>(8, size - i));
    }
    std::atomic_thread_fence(std::memory_order_acquire);
    if (h.seq.load(std::memory_order_relaxed) == s1) return s1 != 0;  // 0: never written
  }
  return false;
}

}  // namespace plc::hmi::ipc

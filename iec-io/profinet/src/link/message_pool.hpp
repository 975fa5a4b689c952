// The message buffers of an in-memory link: each holds one message (up to
// the link's largest, e.g. one Ethernet frame) and a small extra (the UDP
// source), shared by every receiver it goes to through a reference count.
// Buffers are numbered and kept in blocks of kBlockBuffers that never move:
// a receiver may read a buffer it holds a reference to in place
// (MemorySegment::view()) while more buffers are added. The pool doubles
// when every buffer is in use, so after the most messages a link has had in
// flight at once, sending and receiving allocate nothing. Private to
// src/link.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <vector>

namespace plc::profinet::detail {

template <class Extra>
class MessagePool {
 public:
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;  // no buffer

  explicit MessagePool(std::size_t max_bytes) : stride_(max_bytes) {}

  // A buffer with a copy of `bytes` (at most max_bytes) and `extra`, with
  // one reference.
  // Inline: every send's one copy of its message (GCC would keep it out
  // of line, a call per frame).
  [[gnu::always_inline]] std::uint32_t put(std::span<const std::uint8_t> bytes,
                                           const Extra& extra) {
    if (free_count_ == 0) grow();
    const std::uint32_t id = free_[--free_count_];
    const std::size_t n = std::min(bytes.size(), stride_);
    Slot& slot = slots_[id];
    if (n > 0) std::memcpy(slot.data, bytes.data(), n);
    slot.length = static_cast<std::uint32_t>(n);
    slot.refs = 1;
    slot.extra = extra;
    return id;
  }
  void add_ref(std::uint32_t id) { ++slots_[id].refs; }
  // Drops one reference; the last one frees the buffer.
  void release(std::uint32_t id) {
    // free_ has room for every buffer: a store, no push_back() (whose growth
    // path would make each caller save registers for a call never made).
    if (--slots_[id].refs == 0) free_[free_count_++] = id;
  }
  // Where the buffer's bytes are: the same address for as long as the pool
  // lives (blocks are added, never moved).
  [[nodiscard]] std::span<const std::uint8_t> bytes(std::uint32_t id) const {
    return {slots_[id].data, slots_[id].length};
  }
  [[nodiscard]] const Extra& extra(std::uint32_t id) const { return slots_[id].extra; }

 private:
  struct Slot {
    std::uint8_t* data = nullptr;  // in its block, set once
    std::uint32_t length = 0;
    std::uint32_t refs = 0;
    Extra extra{};
  };
  static constexpr std::size_t kBlockBuffers = 16;
  void grow() {
    const std::size_t old = slots_.size();
    const std::size_t n = std::max<std::size_t>(kBlockBuffers, old * 2);  // a multiple of the block
    for (std::size_t b = old / kBlockBuffers; b < n / kBlockBuffers; ++b)
      blocks_.push_back(std::make_unique<std::uint8_t[]>(kBlockBuffers * stride_));
    slots_.resize(n);
    for (std::size_t i = old; i < n; ++i)
      slots_[i].data = blocks_[i / kBlockBuffers].get() + (i % kBlockBuffers) * stride_;
    free_.resize(n);  // every buffer free at once fits: release() never allocates
    for (std::size_t i = n; i > old; --i) free_[free_count_++] = static_cast<std::uint32_t>(i - 1);
  }
  std::size_t stride_;
  std::vector<std::unique_ptr<std::uint8_t[]>> blocks_;
  std::vector<Slot> slots_;
  // The numbers of the free buffers: the first free_count_ of free_ (a
  // stack: the last freed is the next taken).
  std::vector<std::uint32_t> free_;
  std::size_t free_count_ = 0;
};

}  // namespace plc::profinet::detail

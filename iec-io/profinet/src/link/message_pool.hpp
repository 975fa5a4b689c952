// The message buffers of an in-memory link: each holds one message (up to
// the link's largest, e.g. one Ethernet frame) and a small extra (the UDP
// source), shared by every receiver it goes to through a reference count.
// Buffers are numbered and kept in one block; the block doubles when every
// buffer is in use, so after the most messages a link has had in flight at
// once, sending and receiving allocate nothing. Private to src/link.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

namespace plc::profinet::detail {

template <class Extra>
class MessagePool {
 public:
  explicit MessagePool(std::size_t max_bytes) : stride_(max_bytes) {}

  // A buffer with a copy of `bytes` (at most max_bytes) and `extra`, with
  // one reference.
  std::uint32_t put(std::span<const std::uint8_t> bytes, const Extra& extra) {
    if (free_.empty()) grow();
    const std::uint32_t id = free_.back();
    free_.pop_back();
    const std::size_t n = std::min(bytes.size(), stride_);
    if (n > 0) std::memcpy(storage_.data() + std::size_t{id} * stride_, bytes.data(), n);
    slots_[id] = Slot{static_cast<std::uint32_t>(n), 1, extra};
    return id;
  }
  void add_ref(std::uint32_t id) { ++slots_[id].refs; }
  // Drops one reference; the last one frees the buffer.
  void release(std::uint32_t id) {
    if (--slots_[id].refs == 0) free_.push_back(id);  // within the reserved capacity
  }
  [[nodiscard]] std::span<const std::uint8_t> bytes(std::uint32_t id) const {
    return {storage_.data() + std::size_t{id} * stride_, slots_[id].length};
  }
  [[nodiscard]] const Extra& extra(std::uint32_t id) const { return slots_[id].extra; }

 private:
  struct Slot {
    std::uint32_t length = 0;
    std::uint32_t refs = 0;
    Extra extra{};
  };
  void grow() {
    const std::size_t old = slots_.size();
    const std::size_t n = std::max<std::size_t>(kFirstBuffers, old * 2);
    storage_.resize(n * stride_);
    slots_.resize(n);
    free_.reserve(n);  // every buffer free at once fits: release() never allocates
    for (std::size_t i = n; i > old; --i) free_.push_back(static_cast<std::uint32_t>(i - 1));
  }
  static constexpr std::size_t kFirstBuffers = 16;
  std::size_t stride_;
  std::vector<std::uint8_t> storage_;
  std::vector<Slot> slots_;
  std::vector<std::uint32_t> free_;  // numbers of the free buffers
};

}  // namespace plc::profinet::detail

// A FIFO of small values (buffer numbers of the in-memory links) in a ring
// that grows by doubling when full and never shrinks: after the deepest
// queue a link has seen, pushing and popping allocate nothing. Private to
// src/link.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace plc::profinet::detail {

template <class T>
class MessageRing {
 public:
  [[nodiscard]] bool empty() const { return size_ == 0; }
  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] T& front() { return items_[head_]; }
  void pop_front() {
    head_ = (head_ + 1) & (items_.size() - 1);
    --size_;
  }
  void push_back(const T& v) {
    if (size_ == items_.size()) grow();
    items_[(head_ + size_) & (items_.size() - 1)] = v;
    ++size_;
  }

 private:
  // A power of two, so that positions wrap with a mask. Out of line: rare
  // (until the deepest queue), and push_back()'s callers then keep fewer
  // registers for it.
  [[gnu::noinline]] void grow() {
    std::vector<T> bigger(std::max<std::size_t>(kFirstCapacity, items_.size() * 2));
    for (std::size_t i = 0; i < size_; ++i) bigger[i] = items_[(head_ + i) & (items_.size() - 1)];
    items_ = std::move(bigger);
    head_ = 0;
  }
  static constexpr std::size_t kFirstCapacity = 16;
  std::vector<T> items_;
  std::size_t head_ = 0;
  std::size_t size_ = 0;
};

}  // namespace plc::profinet::detail

// The fuzzer's bytes, taken a piece at a time: the targets split one input
// into several telegrams, record answers and command lines. When the input
// runs out every read gives zeros, so any input is a complete script.
//
// (LLVM's FuzzedDataProvider does this too, but it ships with clang only;
// the regression runners are built by g++ in every normal build.)
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>

namespace plc::fuzz {

class FuzzInput {
 public:
  FuzzInput(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  [[nodiscard]] bool empty() const { return pos_ >= size_; }
  [[nodiscard]] std::size_t remaining() const { return size_ - pos_; }

  std::uint8_t byte() { return empty() ? 0 : data_[pos_++]; }
  bool flag() { return (byte() & 1) != 0; }
  // A little-endian integer of sizeof(T) bytes.
  template <class T>
  T integral() {
    T v{};
    std::uint8_t b[sizeof(T)] = {};
    for (std::uint8_t& x : b) x = byte();
    std::memcpy(&v, b, sizeof(T));
    return v;
  }
  // Fills `out` with the next bytes (zeros past the end).
  void fill(std::span<std::uint8_t> out) {
    const std::size_t n = std::min(out.size(), remaining());
    if (n) std::memcpy(out.data(), data_ + pos_, n);
    std::fill(out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), std::uint8_t{0});
    pos_ += n;
  }
  // Up to `n` of the next bytes (fewer at the end).
  std::span<const std::uint8_t> bytes(std::size_t n) {
    n = std::min(n, remaining());
    std::span<const std::uint8_t> s(data_ + pos_, n);
    pos_ += n;
    return s;
  }
  // The text up to the next newline (the newline is consumed).
  std::string_view line() {
    const std::size_t start = pos_;
    while (pos_ < size_ && data_[pos_] != '\n') ++pos_;
    std::string_view s(reinterpret_cast<const char*>(data_) + start, pos_ - start);
    if (pos_ < size_) ++pos_;
    return s;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// Runs the one of `parts` that the input's next byte picks (byte modulo
// their number), each a function of the rest of the input.
template <class... Part>
void run_one_of(FuzzInput& in, Part... parts) {
  const std::size_t pick = in.byte() % sizeof...(Part);
  std::size_t i = 0;
  ((i++ == pick ? parts(in) : void()), ...);
}

}  // namespace plc::fuzz

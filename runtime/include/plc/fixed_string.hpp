// Fixed-capacity string for IEC STRING: no heap, safe truncation.
#pragma once

#include <array>
#include <cstddef>
#include <cstring>
#include <string_view>

namespace plc {

template <std::size_t N>
class FixedString {
 public:
  static constexpr std::size_t capacity = N;

  constexpr FixedString() = default;
  FixedString(std::string_view s) { assign(s); }  // NOLINT: implicit like a literal
  FixedString(const char* s) { assign(s); }       // NOLINT

  // Copies at most N characters; the rest is cut (IEC: implementation-defined,
  // we truncate rather than fail so a scan never throws).
  void assign(std::string_view s) {
    len_ = s.size() < N ? s.size() : N;
    std::memcpy(buf_.data(), s.data(), len_);
    buf_[len_] = '\0';
  }
  FixedString& operator=(std::string_view s) {
    assign(s);
    return *this;
  }
  FixedString& operator=(const char* s) {
    assign(s);
    return *this;
  }

  [[nodiscard]] std::string_view view() const { return {buf_.data(), len_}; }
  [[nodiscard]] const char* c_str() const { return buf_.data(); }
  [[nodiscard]] std::size_t size() const { return len_; }
  [[nodiscard]] bool empty() const { return len_ == 0; }
  operator std::string_view() const { return view(); }  // NOLINT

  friend bool operator==(const FixedString& a, const FixedString& b) {
    return a.view() == b.view();
  }
  friend bool operator==(const FixedString& a, std::string_view b) { return a.view() == b; }

 private:
  std::array<char, N + 1> buf_{};
  std::size_t len_ = 0;
};

}  // namespace plc

// Small byte copies of the scan thread's hot paths: a direct device's
// bytes (virtual time; mostly 2 to 32, copied twice per device and scan), a
// task's bound image spans (often 33 to 64: the filling cell's three are
// 56), a trace's merged variables (Trace::capture; 1 to 16 mostly).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace plc::detail {

// Inline, as two overlapping fixed-size
// copies, instead of a call into the library's memcpy, which costs more
// than such a copy; memcpy above 64 bytes.
[[gnu::always_inline]] inline void copy_bytes(std::uint8_t* dst, const std::uint8_t* src,
                                              std::size_t n) {
  const auto two = [&]<std::size_t K>() {
    std::uint8_t head[K], tail[K];
    std::memcpy(head, src, K);
    std::memcpy(tail, src + n - K, K);
    std::memcpy(dst, head, K);
    std::memcpy(dst + n - K, tail, K);
  };
  if (n >= 16) {
    if (n <= 32) {
      two.template operator()<16>();
    } else if (n <= 64) {
      // The first and the last 32 bytes as four 16-byte moves, through
      // vector registers (byte arrays of 32 went through the stack).
      using V = std::uint8_t __attribute__((vector_size(16)));
      V a, b, c, d;
      std::memcpy(&a, src, 16);
      std::memcpy(&b, src + 16, 16);
      std::memcpy(&c, src + n - 32, 16);
      std::memcpy(&d, src + n - 16, 16);
      std::memcpy(dst, &a, 16);
      std::memcpy(dst + 16, &b, 16);
      std::memcpy(dst + n - 32, &c, 16);
      std::memcpy(dst + n - 16, &d, 16);
    } else {
      std::memcpy(dst, src, n);
    }
  } else if (n >= 8) {
    two.template operator()<8>();
  } else if (n >= 4) {
    two.template operator()<4>();
  } else {
    for (std::size_t i = 0; i < n; ++i) dst[i] = src[i];
  }
}

}  // namespace plc::detail

// Telegrams out of a byte stream (a serial line or a pty delivers bytes in
// arbitrary pieces). On a real line the idle time TSYN (33 bit times)
// separates telegrams; a pty has no idle time, so the telegram structure
// alone delimits them: a start delimiter fixes the length. A byte that
// starts no valid telegram is dropped and counted (resynchronisation), as a
// receiver does after a parity or framing error. No allocation.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "plc/profibus/fdl/telegram.hpp"

namespace plc::profibus::fdl {

class Deframer {
 public:
  // Appends received bytes; bytes beyond the buffer are dropped (counted).
  void push(std::span<const std::uint8_t> bytes);
  // The next whole telegram, if any; its raw bytes in `raw` (valid until
  // the next push/next call).
  bool next(Telegram& t, std::span<const std::uint8_t>* raw = nullptr);
  // Drops what is buffered (a partial telegram after a time-out).
  void reset() { size_ = 0; }
  [[nodiscard]] std::size_t buffered() const { return size_; }
  [[nodiscard]] std::uint64_t dropped_bytes() const { return dropped_; }
  [[nodiscard]] const char* last_error() const { return last_error_; }

 private:
  std::array<std::uint8_t, 2 * kMaxTelegram> buf_{};
  std::array<std::uint8_t, kMaxTelegram> out_{};
  std::size_t size_ = 0;
  std::uint64_t dropped_ = 0;
  const char* last_error_ = "";
};

}  // namespace plc::profibus::fdl

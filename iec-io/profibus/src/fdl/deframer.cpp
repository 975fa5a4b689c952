#include "plc/profibus/fdl/deframer.hpp"

#include <algorithm>
#include <cstring>

namespace plc::profibus::fdl {

void Deframer::push(std::span<const std::uint8_t> bytes) {
  const std::size_t room = buf_.size() - size_;
  const std::size_t n = std::min(room, bytes.size());
  std::copy_n(bytes.data(), n, buf_.data() + size_);  // n may be 0 with a null data()
  size_ += n;
  dropped_ += bytes.size() - n;
}

bool Deframer::next(Telegram& t, std::span<const std::uint8_t>* raw) {
  while (size_ > 0) {
    const DecodeResult r = decode({buf_.data(), size_}, t);
    if (r.status == DecodeStatus::NeedMore) {
      // A buffer full of a beginning that never completes is garbage.
      if (size_ < kMaxTelegram) return false;
      last_error_ = "telegram longer than the longest SD2";
    } else if (r.status == DecodeStatus::Ok) {
      std::memcpy(out_.data(), buf_.data(), r.consumed);
      if (raw) *raw = {out_.data(), r.consumed};
      std::memmove(buf_.data(), buf_.data() + r.consumed, size_ - r.consumed);
      size_ -= r.consumed;
      return true;
    } else {
      last_error_ = r.why;
    }
    // Resynchronise: drop one byte and look again.
    std::memmove(buf_.data(), buf_.data() + 1, size_ - 1);
    --size_;
    ++dropped_;
  }
  return false;
}

}  // namespace plc::profibus::fdl

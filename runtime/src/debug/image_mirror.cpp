#include "image_mirror.hpp"

#include <algorithm>
#include <cstring>

namespace plc::debug {
namespace {

constexpr std::size_t round_up8(std::size_t n) { return (n + 7) / 8 * 8; }

// memcmp compares an unchanged area, then an unchanged chunk, at vector
// speed; only a chunk that differs is looked at word by word.
constexpr std::size_t kChunk = 256;

}  // namespace

ImageMirror::ImageMirror(std::size_t output_bytes, std::size_t memory_bytes)
    : q_bytes_(output_bytes),
      m_bytes_(memory_bytes),
      m_at_(round_up8(output_bytes)),
      copy_(m_at_ + round_up8(memory_bytes), 0) {}

void ImageMirror::diff_area(std::span<const std::uint8_t> src, std::size_t at, recfmt::Buf& out,
                            std::uint32_t& n) {
  // (An empty area may have no data pointer: memcmp must not see it.)
  if (src.empty()) return;
  std::uint8_t* copy = copy_.data() + at;
  if (std::memcmp(src.data(), copy, src.size()) == 0) return;  // the common case
  for (std::size_t c = 0; c < src.size(); c += kChunk) {
    const std::size_t len = std::min(kChunk, src.size() - c);
    // An area of one chunk (the filling cell's %Q) differs: compared above.
    if (len != src.size() && std::memcmp(src.data() + c, copy + c, len) == 0) continue;
    // Whole words with fixed-size loads (a variable-length memcpy per word
    // was a library call: with the PROFIsafe bytes changing every scan the
    // filling cell's %Q chunk is walked every scan); the area's last,
    // partial word alone, zero-padded.
    const std::size_t end = c + len;
    const std::size_t whole_end = c + len / 8 * 8;
    for (std::size_t i = c; i < whole_end; i += 8) {
      std::uint64_t now, was;
      std::memcpy(&now, src.data() + i, 8);
      std::memcpy(&was, copy + i, 8);
      if (now != was) put_word(copy, at, i, now, out, n);
    }
    if (whole_end != end) {
      std::uint64_t now = 0, was;
      std::memcpy(&now, src.data() + whole_end, end - whole_end);
      std::memcpy(&was, copy + whole_end, 8);
      if (now != was) put_word(copy, at, whole_end, now, out, n);
    }
  }
}

void ImageMirror::put_word(std::uint8_t* copy, std::size_t at, std::size_t i, std::uint64_t now,
                           recfmt::Buf& out, std::uint32_t& n) {
  std::memcpy(copy + i, &now, 8);
  out.le(static_cast<std::uint32_t>((at + i) / 8));
  out.bytes(&now, 8);
  ++n;
}

std::uint32_t ImageMirror::diff(std::span<const std::uint8_t> q, std::span<const std::uint8_t> m,
                                recfmt::Buf& out) {
  const std::size_t count_at = out.size();
  out.le(std::uint32_t{0});
  std::uint32_t n = 0;
  diff_area(q.first(std::min(q.size(), q_bytes_)), 0, out, n);
  diff_area(m.first(std::min(m.size(), m_bytes_)), m_at_, out, n);
  out.patch(count_at, n);
  return n;
}

bool ImageMirror::apply(std::span<const std::uint8_t> payload) {
  std::uint32_t n = 0;
  if (payload.size() < 4) return false;
  std::memcpy(&n, payload.data(), 4);
  n = boost::endian::little_to_native(n);
  if (payload.size() != 4 + std::size_t(n) * 12) return false;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint8_t* e = payload.data() + 4 + k * 12;
    std::uint32_t word = 0;
    std::memcpy(&word, e, 4);
    word = boost::endian::little_to_native(word);
    if (word >= words()) return false;
    std::memcpy(copy_.data() + std::size_t(word) * 8, e + 4, 8);
  }
  hash_valid_ = hash_valid_ && n == 0;
  return true;
}

std::uint64_t ImageMirror::hash() {
  if (!hash_valid_) {
    hash_ = recfmt::image_hash(std::span(copy_.data(), q_bytes_),
                               std::span(copy_.data() + m_at_, m_bytes_));
    hash_valid_ = true;
  }
  return hash_;
}

}  // namespace plc::debug

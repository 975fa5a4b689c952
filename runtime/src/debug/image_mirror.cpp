#include "image_mirror.hpp"

#include <algorithm>
#include <cstring>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace plc::debug {
namespace {

constexpr std::size_t round_up8(std::size_t n) { return (n + 7) / 8 * 8; }

// diff_area()'s unit after memcmp: an unchanged chunk costs one memcmp.
constexpr std::size_t kChunk = 256;

// Whether K (32 or 64) bytes at a and b are equal: 16-byte compares and
// one mask with SSE2 (x86-64 always has it), word compares without.
template <std::size_t K>
inline bool same(const std::uint8_t* a, const std::uint8_t* b) {
  static_assert(K == 32 || K == 64);
#ifdef __SSE2__
  const auto eq16 = [&](std::size_t at) {
    return _mm_cmpeq_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(a + at)),
                          _mm_loadu_si128(reinterpret_cast<const __m128i*>(b + at)));
  };
  __m128i all = _mm_and_si128(eq16(0), eq16(16));
  if constexpr (K == 64) all = _mm_and_si128(all, _mm_and_si128(eq16(32), eq16(48)));
  return _mm_movemask_epi8(all) == 0xFFFF;
#else
  std::uint64_t x[K / 8], y[K / 8], d = 0;
  std::memcpy(x, a, K);
  std::memcpy(y, b, K);
  for (std::size_t k = 0; k < K / 8; ++k) d |= x[k] ^ y[k];
  return d == 0;
#endif
}

}  // namespace

ImageMirror::ImageMirror(std::size_t output_bytes, std::size_t memory_bytes)
    : q_bytes_(output_bytes),
      m_bytes_(memory_bytes),
      m_at_(round_up8(output_bytes)),
      copy_(m_at_ + round_up8(memory_bytes), 0) {}

// Whole words with fixed-size loads (a variable-length memcpy per word was
// a library call); the area's last, partial word alone, zero-padded.
// Blocks of 64 bytes, then 32, compared at once, and only a block that
// differs word by word: with the PROFIsafe bytes changing every scan, the
// filling cell's %Q differs every scan in one of its blocks (a walk over
// every word cost 1.3 instructions per byte).
[[gnu::always_inline]] inline void ImageMirror::walk(const std::uint8_t* s, std::uint8_t* copy,
                                                     std::size_t at, std::size_t begin,
                                                     std::size_t end, Out& o) {
  const auto word = [&](std::size_t i) {
    std::uint64_t now, was;
    std::memcpy(&now, s + i, 8);
    std::memcpy(&was, copy + i, 8);
    if (now != was) put_word(copy, at, i, now, o);
  };
  const std::size_t whole_end = begin + (end - begin) / 8 * 8;
  std::size_t i = begin;
  for (; i + 64 <= whole_end; i += 64) {
    if (same<64>(s + i, copy + i)) continue;
    for (std::size_t k = i; k < i + 64; k += 8) word(k);
  }
  if (i + 32 <= whole_end) {
    if (!same<32>(s + i, copy + i))
      for (std::size_t k = i; k < i + 32; k += 8) word(k);
    i += 32;
  }
  for (; i < whole_end; i += 8) word(i);
  if (whole_end != end) {
    std::uint64_t now = 0, was;
    std::memcpy(&now, s + whole_end, end - whole_end);
    std::memcpy(&was, copy + whole_end, 8);
    if (now != was) put_word(copy, at, whole_end, now, o);
  }
}

void ImageMirror::diff_area(std::span<const std::uint8_t> src, std::size_t at, Out& o) {
  // (An empty area may have no data pointer: memcmp must not see it.)
  if (src.empty()) return;
  std::uint8_t* copy = copy_.data() + at;
  const std::uint8_t* s = src.data();
  // An area of more than one chunk: memcmp (the library's, at vector
  // speed) passes it unchanged, then each unchanged chunk; a chunk that
  // differs, and an area of one chunk (no call then), is walked.
  if (src.size() <= kChunk) {
    walk(s, copy, at, 0, src.size(), o);
    return;
  }
  if (std::memcmp(s, copy, src.size()) == 0) return;  // the common case
  for (std::size_t c = 0; c < src.size(); c += kChunk) {
    const std::size_t len = std::min(kChunk, src.size() - c);
    if (std::memcmp(s + c, copy + c, len) != 0) walk(s, copy, at, c, c + len, o);
  }
}

ImageMirror::Words ImageMirror::words_of(bool output, std::size_t byte, std::size_t n) const {
  const std::size_t size = output ? q_bytes_ : m_bytes_;
  const std::size_t at = output ? 0 : m_at_;
  if (byte >= size || n == 0) return {};
  const std::size_t end = std::min(size, byte + n);
  return {static_cast<std::uint32_t>((at + byte) / 8),
          static_cast<std::uint32_t>((at + round_up8(end)) / 8)};
}

void ImageMirror::diff_range(std::span<const std::uint8_t> q, std::span<const std::uint8_t> m,
                             Words w, Out& o) {
  const bool output = std::size_t(w.begin) * 8 < m_at_;
  const std::span<const std::uint8_t> src =
      output ? q.first(std::min(q.size(), q_bytes_)) : m.first(std::min(m.size(), m_bytes_));
  const std::size_t at = output ? 0 : m_at_;
  const std::size_t begin = std::size_t(w.begin) * 8 - at;
  const std::size_t end = std::min(std::size_t(w.end) * 8 - at, src.size());
  if (begin >= end) return;
  walk(src.data(), copy_.data() + at, at, begin, end, o);
}

bool ImageMirror::open(recfmt::Buf& out, Out& o) const {
  std::uint8_t* room = out.room(max_delta_bytes());
  if (!room) return false;
  o.c.p = room;
  o.c.le(std::uint32_t{0});  // the count: close()
  return true;
}

void ImageMirror::close(recfmt::Buf& out, const Out& o, std::uint8_t* count_at) {
  const std::uint32_t n = boost::endian::native_to_little(o.n);
  std::memcpy(count_at, &n, 4);
  out.advance_to(o.c.p);
}

std::uint32_t ImageMirror::diff_words(std::span<const std::uint8_t> q,
                                      std::span<const std::uint8_t> m,
                                      std::initializer_list<std::span<const Words>> ranges,
                                      recfmt::Buf& out) {
  Out o{};
  if (!open(out, o)) return 0;
  std::uint8_t* count_at = o.c.p - 4;
  for (const std::span<const Words> list : ranges)
    for (const Words& w : list) diff_range(q, m, w, o);
  close(out, o, count_at);
  return o.n;
}

void ImageMirror::put_word(std::uint8_t* copy, std::size_t at, std::size_t i, std::uint64_t now,
                           Out& o) {
  std::memcpy(copy + i, &now, 8);
  o.c.le(static_cast<std::uint32_t>((at + i) / 8));
  o.c.bytes(&now, 8);
  ++o.n;
}

std::uint32_t ImageMirror::diff(std::span<const std::uint8_t> q, std::span<const std::uint8_t> m,
                                recfmt::Buf& out) {
  Out o{};
  if (!open(out, o)) return 0;
  std::uint8_t* count_at = o.c.p - 4;
  diff_area(q.first(std::min(q.size(), q_bytes_)), 0, o);
  diff_area(m.first(std::min(m.size(), m_bytes_)), m_at_, o);
  close(out, o, count_at);
  return o.n;
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

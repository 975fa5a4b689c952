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

void ImageMirror::diff_area(std::span<const std::uint8_t> src, std::size_t at, recfmt::Buf& out,
                            std::uint32_t& n) {
  // (An empty area may have no data pointer: memcmp must not see it.)
  if (src.empty()) return;
  std::uint8_t* copy = copy_.data() + at;
  const std::uint8_t* s = src.data();
  // An area of more than one chunk: memcmp (the library's, at vector
  // speed) passes it unchanged, then each unchanged chunk. A chunk that
  // differs, and an area of one chunk (no call then), is compared 64 bytes
  // at a time, then 32, and only a block that differs word by word: with
  // the PROFIsafe bytes changing every scan, the filling cell's %Q (one
  // chunk) differs every scan in one of its four blocks (a walk over every
  // word of the chunk cost 1.3 instructions per byte). Whole words with
  // fixed-size loads (a variable-length memcpy per word was a library
  // call); the area's last, partial word alone, zero-padded.
  const auto word = [&](std::size_t i) {
    std::uint64_t now, was;
    std::memcpy(&now, s + i, 8);
    std::memcpy(&was, copy + i, 8);
    if (now != was) put_word(copy, at, i, now, out, n);
  };
  // [begin, end): begin a multiple of 8; end the area's end or one.
  const auto walk = [&](std::size_t begin, std::size_t end) __attribute__((always_inline)) {
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
      if (now != was) put_word(copy, at, whole_end, now, out, n);
    }
  };
  if (src.size() <= kChunk) {
    walk(0, src.size());
    return;
  }
  if (std::memcmp(s, copy, src.size()) == 0) return;  // the common case
  for (std::size_t c = 0; c < src.size(); c += kChunk) {
    const std::size_t len = std::min(kChunk, src.size() - c);
    if (std::memcmp(s + c, copy + c, len) != 0) walk(c, c + len);
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

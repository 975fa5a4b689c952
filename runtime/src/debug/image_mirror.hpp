// A copy of the global %Q and %M that follows them by deltas, so that the
// recorder's per-scan output hash (recfmt::image_hash over kilobytes of
// image) is computed on the recording's writer thread instead of the scan
// thread. The recorder keeps one mirror on the scan side: at each merge it
// compares the image with it and puts the 8-byte words that changed into
// an image-delta record right before the merge record. It compares the
// whole %Q and %M (diff()) only when it cannot know what changed; at a
// recorded scan's merge, only the words that scan can have changed
// (diff_words(): the task's bound bytes and the debugger's writes), since
// every other word is as the last delta left it. The writer keeps the other: it applies
// each delta, computes the hash of its copy into the merge record that
// follows, and drops the delta record from the file. Both copies start at
// zero and see the same deltas in the same order, so the writer's copy is
// the image as the merge saw it, and the hash is the one the scan would
// have computed.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <span>
#include <vector>

#include "plc/debug/recording_format.hpp"

namespace plc::debug {

// Never in a file: the writer removes it. Payload: u32 words, then per
// word u32 index, u64 value (native order; both ends are this process).
inline constexpr recfmt::Type kImageDelta = static_cast<recfmt::Type>('d');

class ImageMirror {
 public:
  ImageMirror(std::size_t output_bytes, std::size_t memory_bytes);

  // Scan side: appends to `out` (begun as a kImageDelta record, with room
  // for max_delta_bytes()) the words of %Q and %M that differ from the
  // copy, and takes them into the copy. Returns the number of words.
  std::uint32_t diff(std::span<const std::uint8_t> q, std::span<const std::uint8_t> m,
                     recfmt::Buf& out);

  // Words of the copy, numbered as in the delta and the hash.
  using Words = recfmt::ImageWords;
  // The words that hold bytes [byte, byte + n) of %Q (output) or %M.
  [[nodiscard]] Words words_of(bool output, std::size_t byte, std::size_t n) const;
  // As diff(), over `ranges` only: the caller knows that no other word of
  // %Q and %M can have changed since the last diff. Ranges may overlap (a
  // word diffed twice is in the delta once).
  std::uint32_t diff_words(std::span<const std::uint8_t> q, std::span<const std::uint8_t> m,
                           std::initializer_list<std::span<const Words>> ranges, recfmt::Buf& out);
  // Writer side: takes a delta's payload into the copy (false: malformed).
  bool apply(std::span<const std::uint8_t> payload);
  // recfmt::image_hash of the copy (cached until the next apply()).
  std::uint64_t hash();

  // Payload bytes of a delta in which every word changed.
  [[nodiscard]] std::size_t max_delta_bytes() const { return 4 + words() * 12; }

 private:
  [[nodiscard]] std::size_t words() const { return copy_.size() / 8; }
  // The delta being written: a cursor into room for every word (checked
  // once per diff, Buf::room), and the words in it so far.
  struct Out {
    recfmt::Put c;
    std::uint32_t n = 0;
  };
  // Opens a delta's payload in `out` (false: no room, the buffer overflowed).
  bool open(recfmt::Buf& out, Out& o) const;
  static void close(recfmt::Buf& out, const Out& o, std::uint8_t* count_at);
  void diff_area(std::span<const std::uint8_t> src, std::size_t at, Out& o);
  void diff_range(std::span<const std::uint8_t> q, std::span<const std::uint8_t> m, Words w,
                  Out& o);
  // Bytes [begin, end) of an area (src, at its offset `at` in the copy):
  // begin a multiple of 8, end one or the area's end.
  static void walk(const std::uint8_t* src, std::uint8_t* copy, std::size_t at, std::size_t begin,
                   std::size_t end, Out& o);
  // Takes the word at copy[i] (i from the area's start `at`) into the copy
  // and the delta.
  static void put_word(std::uint8_t* copy, std::size_t at, std::size_t i, std::uint64_t now,
                       Out& o);

  std::size_t q_bytes_, m_bytes_, m_at_;  // m_at_: %Q padded to whole words
  std::vector<std::uint8_t> copy_;        // %Q, zero padding, %M, zero padding
  std::uint64_t hash_ = 0;
  bool hash_valid_ = false;
};

}  // namespace plc::debug

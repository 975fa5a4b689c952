// The recorder's image mirror (runtime/src/debug/image_mirror.hpp): the
// scan side's diff() must put into the delta exactly the 8-byte words of
// %Q and %M that changed since its last diff, so that the writer's copy,
// applying the deltas, hashes to what the scan's image hashes to. Checked
// against a plain word-by-word comparison over area sizes around its
// block (32, 64 bytes), chunk (256) and word boundaries, and over random
// changes: none, a few bytes, whole runs.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "../../runtime/src/debug/image_mirror.hpp"
#include "plc/debug/recording_format.hpp"

using namespace plc::debug;

namespace {

// The words of `now` (zero-padded to whole words) that differ from `was`.
std::uint32_t words_changed(const std::vector<std::uint8_t>& was,
                            const std::vector<std::uint8_t>& now) {
  std::uint32_t n = 0;
  for (std::size_t i = 0; i < now.size(); i += 8) {
    bool same = true;
    for (std::size_t k = i; k < i + 8 && k < now.size(); ++k) same = same && was[k] == now[k];
    n += same ? 0 : 1;
  }
  return n;
}

void mutate(std::vector<std::uint8_t>& v, std::mt19937& rng) {
  if (v.empty()) return;
  switch (rng() % 4) {
    case 0:  // nothing changes (the common scan)
      break;
    case 1:  // a few bytes
      for (int k = 0, n = 1 + int(rng() % 4); k < n; ++k)
        v[rng() % v.size()] = static_cast<std::uint8_t>(rng());
      break;
    case 2: {  // a run
      const std::size_t at = rng() % v.size();
      const std::size_t len = 1 + rng() % (v.size() - at);
      for (std::size_t k = at; k < at + len; ++k) v[k] = static_cast<std::uint8_t>(rng());
      break;
    }
    default:  // the last byte (a partial word)
      v.back() = static_cast<std::uint8_t>(v.back() + 1);
  }
}

}  // namespace

TEST(ImageMirror, DeltaHoldsExactlyTheChangedWordsAndTheWriterHashMatches) {
  std::mt19937 rng(23);
  const std::size_t q_sizes[] = {0,   1,   7,   8,   13,  31,  32,  33,  63,   64,  65,
                                 100, 255, 256, 257, 300, 511, 512, 513, 1000, 5120};
  const std::size_t m_sizes[] = {0, 5, 64, 700};
  for (std::size_t qn : q_sizes) {
    for (std::size_t mn : m_sizes) {
      ImageMirror scan_side(qn, mn), writer_side(qn, mn);
      std::vector<std::uint8_t> q(qn, 0), m(mn, 0);
      recfmt::Buf delta;
      delta.reserve_fixed(recfmt::kHead + scan_side.max_delta_bytes() + 4);
      for (int step = 0; step < 200; ++step) {
        const auto q_was = q, m_was = m;
        mutate(q, rng);
        mutate(m, rng);
        delta.begin(kImageDelta);
        const std::uint32_t n = scan_side.diff(q, m, delta);
        ASSERT_FALSE(delta.overflow());
        ASSERT_EQ(n, words_changed(q_was, q) + words_changed(m_was, m))
            << "%Q " << qn << " %M " << mn << " step " << step;
        const auto payload = delta.view().subspan(recfmt::kHead);
        ASSERT_TRUE(writer_side.apply(payload));
        ASSERT_EQ(writer_side.hash(), recfmt::image_hash(q, m))
            << "%Q " << qn << " %M " << mn << " step " << step;
      }
    }
  }
}

// diff_words(): the recorder's diff at a recorded scan's merge, over the
// words that scan can have changed (its task's bound bytes, the debugger's
// writes). Changes inside the ranges give the same delta as a whole diff;
// ranges that overlap put a word in the delta once; a change outside them
// is not looked at (the contract: the caller knows nothing else changed),
// and the next whole diff() takes it.
TEST(ImageMirror, DiffOverWordRangesTakesTheChangesInsideThemOnce) {
  const std::size_t qn = 61, mn = 300;  // partial last words in both areas
  ImageMirror scan_side(qn, mn), writer_side(qn, mn);
  std::vector<std::uint8_t> q(qn, 0), m(mn, 0);
  recfmt::Buf delta;
  delta.reserve_fixed(recfmt::kHead + scan_side.max_delta_bytes() + 4);
  const auto take = [&](std::uint32_t n_expected, const char* what) {
    const auto payload = delta.view().subspan(recfmt::kHead);
    std::uint32_t n = 0;
    std::memcpy(&n, payload.data(), 4);
    EXPECT_EQ(n, n_expected) << what;
    ASSERT_TRUE(writer_side.apply(payload)) << what;
  };
  using W = ImageMirror::Words;
  // Bytes 3..5 of %Q (word 0), 57..60 of %Q (its last, partial word 7),
  // %M bytes 100..116 (three words), %M byte 299 (its last, partial word).
  const W q_head = scan_side.words_of(true, 3, 3), q_tail = scan_side.words_of(true, 57, 10);
  const W m_mid = scan_side.words_of(false, 100, 17), m_end = scan_side.words_of(false, 299, 1);
  EXPECT_EQ(q_head.begin, 0u);
  EXPECT_EQ(q_head.end, 1u);
  EXPECT_EQ(q_tail.begin, 7u);
  EXPECT_EQ(q_tail.end, 8u);  // clipped to %Q's 61 bytes
  EXPECT_EQ(m_mid.begin, 8u + 12u);
  EXPECT_EQ(m_mid.end, 8u + 15u);
  EXPECT_EQ(m_end.begin, 8u + 37u);
  EXPECT_EQ(m_end.end, 8u + 38u);
  EXPECT_EQ(scan_side.words_of(true, 61, 2).end, 0u) << "outside %Q: no words";

  q[4] = 1;
  q[60] = 2;
  m[100] = 3;
  m[116] = 4;
  m[299] = 5;
  const std::vector<W> bound = {q_head, q_tail, m_mid};
  const std::vector<W> marks = {m_end, m_mid};  // m_mid twice: in the delta once
  delta.begin(kImageDelta);
  EXPECT_EQ(scan_side.diff_words(q, m, {bound, marks}, delta), 5u);
  take(5, "inside the ranges");
  EXPECT_EQ(writer_side.hash(), recfmt::image_hash(q, m));

  m[200] = 6;  // outside every range
  q[4] = 7;
  delta.begin(kImageDelta);
  EXPECT_EQ(scan_side.diff_words(q, m, {bound}, delta), 1u);
  take(1, "outside the ranges");
  EXPECT_NE(writer_side.hash(), recfmt::image_hash(q, m)) << "m[200] was not looked at";
  delta.begin(kImageDelta);
  EXPECT_EQ(scan_side.diff(q, m, delta), 1u);
  take(1, "the next whole diff");
  EXPECT_EQ(writer_side.hash(), recfmt::image_hash(q, m));

  delta.begin(kImageDelta);
  EXPECT_EQ(scan_side.diff_words(q, m, {bound, marks}, delta), 0u) << "nothing changed since";
}

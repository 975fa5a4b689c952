// CRC2 of one PROFIsafe connection in a few table steps per telegram, bit
// for bit the CRC2 of safety_pdu.hpp (compute_crc2()).
//
// FOR TEST BENCHES AND SIMULATION ONLY, NOT CERTIFIED SAFETY SOFTWARE.
//
// CRC2 is fed the CRC1 seed, the control/status byte, the F-data reversed
// (the "head") and then the consecutive number as 4 bytes (the "tail"; order
// in safety_pdu.hpp). A CRC without final XOR is linear over GF(2), so
//   CRC2 = Z4(register after the head) ^ TAIL(consecutive number),
// with Z4 = the register run on through 4 zero bytes and TAIL = the CRC of
// (low, middle, high, 0x00) from register 0, which three constant tables
// give: one per byte of the 24-bit number, each entry the CRC of that byte
// in its place followed by the zero bytes after it.
//
// From one telegram to the next of a connection only the number changes,
// and the toggle bit (bit 5) of the control/status byte alternates: the
// F-data and the other bits stay as long as the process data does. So the
// cache keeps Z4(head) for the last head seen with each toggle value, and a
// telegram whose head (seed, byte, F-data) is one of those two costs a
// compare of the head (packed into two words) and one table look-up (three
// when the number's upper 16 bits change). Any other head is computed in
// full and replaces the one of its toggle value: the result never depends
// on what the cache held. Only the 3-byte CRC2 (F-data up to 12 bytes) is
// cached; the 4-byte one is computed in full.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "plc/fb/safety/safety_pdu.hpp"

namespace plc::safety {

namespace detail {
// kCrc2Tail[k][b]: the 24-bit CRC2 from register 0 of the 4 number bytes
// with b in place k (0 = least significant) and 0 in the others.
constexpr std::array<std::array<std::uint32_t, 256>, 3> make_crc2_tail() {
  std::array<std::array<std::uint32_t, 256>, 3> t{};
  for (std::size_t k = 0; k < 3; ++k)
    for (std::uint32_t b = 0; b < 256; ++b) {
      std::uint32_t c = 0;
      for (std::size_t i = 0; i < 4; ++i)
        c = Crc2x24Engine::update_byte(c, i == k ? static_cast<std::uint8_t>(b) : std::uint8_t{0});
      t[k][b] = c;
    }
  return t;
}
inline constexpr std::array<std::array<std::uint32_t, 256>, 3> kCrc2Tail = make_crc2_tail();
}  // namespace detail

class Crc2Cache {
 public:
  using Engine = Crc2x24Engine;
  static constexpr std::size_t kMaxCachedFData = 12;  // crc2_length() == 3 up to here

  // compute_crc2(fdata, cb_sb, cons_nr, crc1_seed), cheaper when the head
  // repeats.
  std::uint32_t crc2(std::span<const std::uint8_t> fdata, std::uint8_t cb_sb, std::uint32_t cons_nr,
                     std::uint16_t crc1_seed) {
    if (fdata.size() > kMaxCachedFData) return compute_crc2(fdata, cb_sb, cons_nr, crc1_seed);
    return cached_crc2(fdata, cb_sb, cons_nr, crc1_seed);
  }

  // write_pdu() and check_pdu() of safety_pdu.hpp with this cache's CRC2.
  void write_pdu(std::span<std::uint8_t> pdu, std::span<const std::uint8_t> fdata,
                 std::uint8_t cb_sb, std::uint32_t cons_nr, std::uint16_t crc1_seed) {
    const std::size_t n = fdata.size();
    for (std::size_t i = 0; i < n; ++i) pdu[i] = fdata[i];
    seal_pdu(pdu, n, cb_sb, cons_nr, crc1_seed);
  }
  // write_pdu() for F-data already in pdu[0, fdata_len): writes the
  // control/status byte and CRC2 behind it (no copy of the data).
  [[gnu::always_inline]] void seal_pdu(std::span<std::uint8_t> pdu, std::size_t fdata_len,
                                       std::uint8_t cb_sb, std::uint32_t cons_nr,
                                       std::uint16_t crc1_seed) {
    if (fdata_len <= kMaxCachedFData) {  // crc2_length() == 3
      const std::uint32_t c = cached_crc2(pdu.first(fdata_len), cb_sb, cons_nr, crc1_seed);
      // The control/status byte and the 3-byte CRC2 behind it (most
      // significant first) as one big-endian word: one store, not four.
      store_be32(pdu.data() + fdata_len, static_cast<std::uint32_t>(cb_sb) << 24 | (c & 0xFFFFFFu));
      return;
    }
    seal_uncached(pdu, fdata_len, cb_sb, cons_nr, crc1_seed);
  }
  [[gnu::always_inline]] bool check_pdu(std::span<const std::uint8_t> pdu, std::size_t fdata_len,
                                        std::uint32_t cons_nr, std::uint16_t crc1_seed) {
    if (pdu.size() < pdu_size(fdata_len)) return false;
    if (fdata_len <= kMaxCachedFData) {  // crc2_length() == 3
      // The status byte and the 3-byte CRC2 (most significant first) as one
      // big-endian word (pdu_size() = fdata_len + 4 bytes are there).
      const std::uint32_t w = load_be32(pdu.data() + fdata_len);
      const auto cb_sb = static_cast<std::uint8_t>(w >> 24);
      return cached_crc2(pdu.first(fdata_len), cb_sb, cons_nr, crc1_seed) == (w & 0xFFFFFFu);
    }
    return compute_crc2(pdu.first(fdata_len), pdu[fdata_len], cons_nr, crc1_seed) ==
           get_crc2(pdu, fdata_len);
  }

 private:
  // A head packed into two words, compared as two: `key` holds the seed,
  // the control/status byte, the F-data length + 1 (so no head is 0, the
  // empty slot) and F-data bytes 0..3; `rest` bytes 4..11 (0 beyond the
  // length). For one length the packing is one-to-one, and the length is
  // in `key`, so equal words are equal heads.
  struct Key {
    std::uint64_t key = 0;
    std::uint64_t rest = 0;
  };
  [[gnu::always_inline]] static Key pack(std::span<const std::uint8_t> fdata, std::uint8_t cb_sb,
                                         std::uint16_t seed) {
    const std::size_t n = fdata.size();  // <= kMaxCachedFData
    const std::uint8_t* d = fdata.data();
    std::uint64_t lo = 0, hi = 0;
    if (n == 4) {  // the usual F-data (NORD: 4 bytes each way): one load
      std::uint32_t w;
      std::memcpy(&w, d, 4);
      lo = w;
    } else {
      for (std::size_t i = 0; i < n && i < 4; ++i)
        lo |= static_cast<std::uint64_t>(d[i]) << (8 * i);
      for (std::size_t i = 4; i < n; ++i) hi |= static_cast<std::uint64_t>(d[i]) << (8 * (i - 4));
    }
    return {static_cast<std::uint64_t>(seed) | static_cast<std::uint64_t>(cb_sb) << 16 |
                static_cast<std::uint64_t>(n + 1) << 24 | lo << 32,
            hi};
  }

  // seal_pdu(), check_pdu() and this are always inline: four per exchange,
  // each a few instructions when the head is cached.
  [[gnu::always_inline]] std::uint32_t cached_crc2(std::span<const std::uint8_t> fdata,
                                                   std::uint8_t cb_sb, std::uint32_t cons_nr,
                                                   std::uint16_t crc1_seed) {
    const Key k = pack(fdata, cb_sb, crc1_seed);
    Head& h = heads_[(cb_sb >> 5) & 1u];
    // Equal keys have equal lengths, and up to 4 bytes of F-data `rest` is
    // 0 in every head of that length: the key alone decides (the length is
    // a constant where the cache is inlined).
    if (h.k.key != k.key || (fdata.size() > 4 && h.k.rest != k.rest))
      h.take(k, fdata, cb_sb, crc1_seed);
    const auto& t = detail::kCrc2Tail;
    // The middle and high bytes' part of TAIL, once per change of
    // cons_nr >> 8 (every 256th telegram of a connection counting on).
    const std::uint32_t hi = cons_nr >> 8;
    if (hi != tail_hi_of_) {
      tail_hi_of_ = hi;
      tail_hi_ = t[1][hi & 0xFFu] ^ t[2][(hi >> 8) & 0xFFu];
    }
    return h.z4 ^ t[0][cons_nr & 0xFFu] ^ tail_hi_;
  }

  struct Head {
    Key k;                 // the head (pack()); key 0: empty
    std::uint32_t z4 = 0;  // Z4(register after seed, cb, F-data reversed)

    void take(const Key& key, std::span<const std::uint8_t> fdata, std::uint8_t cb_sb,
              std::uint16_t s) {
      k = key;
      std::uint32_t c = Engine::update_byte(s, cb_sb);
      for (std::size_t i = fdata.size(); i-- > 0;) c = Engine::update_byte(c, fdata[i]);
      for (int j = 0; j < 4; ++j) c = Engine::update_byte(c, 0x00);
      z4 = c;
    }
  };

  [[gnu::always_inline]] static std::uint32_t load_be32(const std::uint8_t* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    if constexpr (std::endian::native == std::endian::little) v = __builtin_bswap32(v);
    return v;
  }
  [[gnu::always_inline]] static void store_be32(std::uint8_t* p, std::uint32_t v) {
    if constexpr (std::endian::native == std::endian::little) v = __builtin_bswap32(v);
    std::memcpy(p, &v, 4);
  }

  // write_pdu()'s seal for F-data over 12 bytes (the 4-byte CRC2, not
  // cached); out of line, rare.
  [[gnu::noinline]] static void seal_uncached(std::span<std::uint8_t> pdu, std::size_t n,
                                              std::uint8_t cb_sb, std::uint32_t cons_nr,
                                              std::uint16_t crc1_seed) {
    pdu[n] = cb_sb;
    put_crc2(pdu, n, compute_crc2(pdu.first(n), cb_sb, cons_nr, crc1_seed));
  }

  static void put_crc2(std::span<std::uint8_t> pdu, std::size_t n, std::uint32_t c) {
    const std::size_t len = crc2_length(n);
    for (std::size_t i = 0; i < len; ++i)
      pdu[n + 1 + i] = static_cast<std::uint8_t>(c >> (8 * (len - 1 - i)));
  }
  static std::uint32_t get_crc2(std::span<const std::uint8_t> pdu, std::size_t n) {
    const std::size_t len = crc2_length(n);
    std::uint32_t got = 0;
    for (std::size_t i = 0; i < len; ++i) got = (got << 8) | pdu[n + 1 + i];
    return got;
  }

  std::array<Head, 2> heads_{};
  // kCrc2Tail[1][b1] ^ kCrc2Tail[2][b2] of the number bytes in tail_hi_of_
  // (cons_nr >> 8); both 0 at first, which is that entry for number 0.
  std::uint32_t tail_hi_of_ = 0, tail_hi_ = 0;
};

}  // namespace plc::safety

// Building and checking one PROFIsafe V2 PDU: F-data, then the control or
// status byte, then CRC2 (spec nord-profisafe.md §2.1, §2.6).
//
// FOR TEST BENCHES AND SIMULATION ONLY, NOT CERTIFIED SAFETY SOFTWARE.
//
// CRC2 coverage and order, from REAL TRAFFIC (shared/reference/
// profisafe-wire-vectors.md: all 1,809 distinct device telegrams of a public
// capture fit this order and no other; tests/safety/test_wire_vectors.cpp):
//   register = CRC1 (F_Par_CRC); then the status/control byte; then the
//   F-data from its LAST byte to its FIRST; then the virtual consecutive
//   number as 4 bytes, least significant first (low, middle, high, 0x00).
//   The consecutive number is not transmitted. CRC2 is written big-endian
//   after the status/control byte.
// Readings that still rest on the standard alone (the capture cannot settle
// them): the host -> device control telegram uses the same order (control
// byte, F-output data reversed, number), and the 4-byte CRC2 (F-data above
// 12 bytes) feeds the same bytes in the same order to its 32-bit generator.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "plc/fb/safety/crc.hpp"

namespace plc::safety {

// Longest F-data of one PDU (spec §2.1: 13..123 bytes use a 4-byte CRC).
inline constexpr std::size_t kMaxFData = 123;

// CRC2 length for n bytes of F-data: 3 up to 12 bytes, 4 above (spec §2.1).
constexpr std::size_t crc2_length(std::size_t fdata_len) { return fdata_len <= 12 ? 3 : 4; }
constexpr std::size_t pdu_size(std::size_t fdata_len) {
  return fdata_len + 1 + crc2_length(fdata_len);
}

// 24-bit consecutive number: 1 .. 0xFFFFFF, then wraps to 1; 0 only after a
// reset (spec §2.6, [SPEC]).
constexpr std::uint32_t next_cons_nr(std::uint32_t cn) { return cn >= 0xFFFFFFu ? 1u : cn + 1u; }

// CRC2 over control/status byte + F-data (reversed) + consecutive number,
// seeded with CRC1 (order: see the top of this file).
template <class Engine>
constexpr std::uint32_t crc2_with(std::span<const std::uint8_t> fdata, std::uint8_t cb_sb,
                                  std::uint32_t cons_nr, std::uint16_t crc1_seed) {
  std::uint32_t c = Engine::update_byte(crc1_seed, cb_sb);
  for (std::size_t i = fdata.size(); i-- > 0;) c = Engine::update_byte(c, fdata[i]);
  c = Engine::update_byte(c, static_cast<std::uint8_t>(cons_nr));
  c = Engine::update_byte(c, static_cast<std::uint8_t>(cons_nr >> 8));
  c = Engine::update_byte(c, static_cast<std::uint8_t>(cons_nr >> 16));
  return Engine::update_byte(c, 0x00);  // the virtual number is 24 bit
}
constexpr std::uint32_t compute_crc2(std::span<const std::uint8_t> fdata, std::uint8_t cb_sb,
                                     std::uint32_t cons_nr, std::uint16_t crc1_seed) {
  return crc2_length(fdata.size()) == 3
             ? crc2_with<Crc2x24Engine>(fdata, cb_sb, cons_nr, crc1_seed)
             : crc2_with<Crc2x32Engine>(fdata, cb_sb, cons_nr, crc1_seed);
}

// Writes data, cb/sb and CRC2 into `pdu` (size pdu_size(data.size())).
inline void write_pdu(std::span<std::uint8_t> pdu, std::span<const std::uint8_t> fdata,
                      std::uint8_t cb_sb, std::uint32_t cons_nr, std::uint16_t crc1_seed) {
  const std::size_t n = fdata.size();
  for (std::size_t i = 0; i < n; ++i) pdu[i] = fdata[i];
  pdu[n] = cb_sb;
  const std::uint32_t c = compute_crc2(fdata, cb_sb, cons_nr, crc1_seed);
  const std::size_t len = crc2_length(n);
  for (std::size_t i = 0; i < len; ++i)
    pdu[n + 1 + i] = static_cast<std::uint8_t>(c >> (8 * (len - 1 - i)));
}

// True if the PDU (F-data length fdata_len) carries the right CRC2 for cons_nr.
inline bool check_pdu(std::span<const std::uint8_t> pdu, std::size_t fdata_len,
                      std::uint32_t cons_nr, std::uint16_t crc1_seed) {
  if (pdu.size() < pdu_size(fdata_len)) return false;
  const std::uint32_t c = compute_crc2(pdu.first(fdata_len), pdu[fdata_len], cons_nr, crc1_seed);
  const std::size_t len = crc2_length(fdata_len);
  std::uint32_t got = 0;
  for (std::size_t i = 0; i < len; ++i) got = (got << 8) | pdu[fdata_len + 1 + i];
  return got == c;
}

}  // namespace plc::safety

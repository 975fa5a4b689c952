// PROFIsafe CRCs: CRC1 (F_Par_CRC, 16 bit) and CRC2 (3- or 4-byte telegram CRC).
//
// FOR TEST BENCHES AND SIMULATION ONLY, NOT CERTIFIED SAFETY SOFTWARE.
//
// The NORD manual gives no polynomial or seeding (spec nord-profisafe.md §2.2,
// §2.6, §8.5 item 1). Where each value comes from:
//   * CRC2 (3 byte): 24 bit, generator 0x5D6DCB (0x15D6DCB with the x^24
//     term), MSB first, no reflection, no final XOR, start value CRC1:
//     REAL TRAFFIC (shared/reference/profisafe-wire-vectors.md, 1,809 device
//     telegrams of a public capture); the byte order is in safety_pdu.hpp;
//   * CRC1: 16 bit, generator 0x4EAB, MSB first, no reflection, start 0, no
//     final XOR, fields big-endian in block order: [SPEC] (the vectors file
//     says it agrees with its source's published F_Par_CRC values, but gives
//     no parameter block we could check ourselves);
//   * CRC2 (4 byte): 32 bit, generator 0xF4ACFB13: [SPEC] only, TO BE
//     VERIFIED AGAINST IEC 61784-3-3 / PI 3.192 (NORD uses the 3-byte CRC).
// One table-driven engine, parameterised by width and generator, so that the
// tests can check the engine itself against published catalogue CRCs that use
// the same algorithm class (MSB first, no reflection).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace plc::safety {

template <unsigned Width, std::uint32_t Poly>
struct MsbCrc {
  static_assert(Width >= 8 && Width <= 32);
  static constexpr std::uint32_t kMask =
      Width == 32 ? 0xFFFFFFFFu : static_cast<std::uint32_t>((1ull << Width) - 1);
  static constexpr std::uint32_t kTop = 1u << (Width - 1);

  static constexpr std::array<std::uint32_t, 256> make_table() {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i << (Width - 8);
      for (int b = 0; b < 8; ++b) c = (c & kTop) ? ((c << 1) ^ Poly) & kMask : (c << 1) & kMask;
      t[i] = c;
    }
    return t;
  }
  static constexpr std::array<std::uint32_t, 256> kTable = make_table();

  // Continue a CRC over `bytes` from register value `crc`.
  static constexpr std::uint32_t update(std::uint32_t crc, std::span<const std::uint8_t> bytes) {
    for (std::uint8_t b : bytes) {
      const std::uint32_t idx = ((crc >> (Width - 8)) ^ b) & 0xFFu;
      crc = ((crc << 8) ^ kTable[idx]) & kMask;
    }
    return crc;
  }
  static constexpr std::uint32_t update_byte(std::uint32_t crc, std::uint8_t b) {
    const std::uint32_t idx = ((crc >> (Width - 8)) ^ b) & 0xFFu;
    return ((crc << 8) ^ kTable[idx]) & kMask;
  }
};

using Crc1Engine = MsbCrc<16, 0x4EABu>;         // [SPEC] verify
using Crc2x24Engine = MsbCrc<24, 0x5D6DCBu>;    // real traffic (wire vectors)
using Crc2x32Engine = MsbCrc<32, 0xF4ACFB13u>;  // [SPEC] verify (4-byte case)

// CRC1 over the F-parameter bytes (start value 0, [SPEC]).
constexpr std::uint16_t crc1(std::span<const std::uint8_t> fpar_bytes) {
  return static_cast<std::uint16_t>(Crc1Engine::update(0, fpar_bytes));
}

}  // namespace plc::safety

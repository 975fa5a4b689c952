// Reference CRC for the safety tests, independent of the product's
// table-driven engine (crc.hpp): bit at a time, MSB first, no reflection,
// no final XOR, register width 8..32 bits.
#pragma once

#include <cstdint>
#include <vector>

namespace safety_test {

inline std::uint32_t bitwise_crc(std::uint32_t poly, unsigned width, std::uint32_t init,
                                 const std::vector<std::uint8_t>& data) {
  const std::uint64_t mask = (1ull << width) - 1;
  std::uint64_t c = init;
  for (std::uint8_t b : data) {
    c ^= static_cast<std::uint64_t>(b) << (width - 8);
    for (int i = 0; i < 8; ++i)
      c = (c & (1ull << (width - 1))) ? ((c << 1) ^ poly) & mask : (c << 1) & mask;
  }
  return static_cast<std::uint32_t>(c);
}

}  // namespace safety_test

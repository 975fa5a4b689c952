// DP configuration data (Chk_Cfg / Get_Cfg, a GSD module's Cfg bytes;
// EN 50170 vol. 2, DP §8.3.8 "Identifier byte"):
//   general identifier: bits 0-3 length - 1, bits 4-5 00 special format /
//     01 input / 10 output / 11 input and output, bit 6 words (else bytes),
//     bit 7 consistency over the whole length;
//   special identifier (bits 4-5 = 00): bits 0-3 the count of manufacturer
//     bytes at the end, bits 6-7 00 empty slot (with 0 manufacturer bytes) /
//     01 an input length byte follows / 10 an output length byte / 11 an
//     output then an input length byte; a length byte: bits 0-5 length - 1,
//     bit 6 words, bit 7 consistency.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace plc::profibus::dp {

struct CfgSizes {
  std::size_t input_bytes = 0;
  std::size_t output_bytes = 0;
  std::size_t identifiers = 0;  // modules (identifiers) in the data
};

// The I/O sizes of a whole configuration; nullopt when it is malformed (a
// length byte or manufacturer byte missing at the end).
std::optional<CfgSizes> cfg_sizes(std::span<const std::uint8_t> cfg);

// "B7 FF" for messages.
std::string hex(std::span<const std::uint8_t> bytes);

}  // namespace plc::profibus::dp

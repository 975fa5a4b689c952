// IEC 61131-3 direct addresses: %IX0.0, %IB4, %IW6, %ID8, %IL16, %QX1.7,
// %MW10, and the short bit form %I0.0.
//
// Addressing is by BYTE offset, as in Siemens STEP 7 (%IW6 = bytes 6 and 7,
// %ID8 = bytes 8..11), not by element index as in CODESYS (where %IW6 would
// be bytes 12 and 13). Our devices are PROFINET/PROFIBUS devices whose
// manuals and engineers count in bytes, so byte offsets avoid a translation.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "plc/types.hpp"

namespace plc::io {

enum class Area : std::uint8_t { Input, Output, Memory };              // %I, %Q, %M
enum class AddrSize : std::uint8_t { Bit, Byte, Word, DWord, LWord };  // X B W D L

struct IecAddress {
  Area area = Area::Input;
  AddrSize size = AddrSize::Bit;
  std::uint32_t byte = 0;
  std::uint8_t bit = 0;  // only for AddrSize::Bit

  [[nodiscard]] std::size_t width_bytes() const;  // 1 for a bit
  [[nodiscard]] std::string to_string() const;
  friend bool operator==(const IecAddress&, const IecAddress&) = default;
};

char area_letter(Area a);

struct AddressParseResult {
  std::optional<IecAddress> address;
  std::string error;  // why it is not an address, when address is empty
};

// Parses and validates the syntax ("%QX0.8" -> error "bit number 8 out of
// range 0..7"). Range checks against the image size are separate.
AddressParseResult parse_iec_address(std::string_view text);

// The size an address needs for a variable of type t (BOOL -> Bit, INT ->
// Word, ...); empty for STRING.
std::optional<AddrSize> addr_size_for(VarType t);

}  // namespace plc::io

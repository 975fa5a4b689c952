#include "plc/io/iec_address.hpp"

#include <cctype>
#include <charconv>

namespace plc::io {

char area_letter(Area a) {
  switch (a) {
    case Area::Input:
      return 'I';
    case Area::Output:
      return 'Q';
    case Area::Memory:
      return 'M';
  }
  return '?';
}

std::size_t IecAddress::width_bytes() const {
  switch (size) {
    case AddrSize::Bit:
    case AddrSize::Byte:
      return 1;
    case AddrSize::Word:
      return 2;
    case AddrSize::DWord:
      return 4;
    case AddrSize::LWord:
      return 8;
  }
  return 1;
}

std::string IecAddress::to_string() const {
  static constexpr char sz[] = {'X', 'B', 'W', 'D', 'L'};
  std::string s = "%";
  s += area_letter(area);
  s += sz[static_cast<int>(size)];
  s += std::to_string(byte);
  if (size == AddrSize::Bit) {
    s += '.';
    s += std::to_string(bit);
  }
  return s;
}

AddressParseResult parse_iec_address(std::string_view t) {
  const std::string text(t);
  auto fail = [&](const std::string& why) {
    return AddressParseResult{std::nullopt, "invalid IEC address '" + text + "': " + why};
  };
  if (t.empty() || t[0] != '%') return fail("must start with '%' (e.g. %IX0.0, %QW4)");
  t.remove_prefix(1);
  if (t.empty()) return fail("missing area letter I, Q or M");
  IecAddress a;
  switch (std::toupper(static_cast<unsigned char>(t[0]))) {
    case 'I':
      a.area = Area::Input;
      break;
    case 'Q':
      a.area = Area::Output;
      break;
    case 'M':
      a.area = Area::Memory;
      break;
    default:
      return fail(std::string("unknown area '") + t[0] + "' (expected I, Q or M)");
  }
  t.remove_prefix(1);
  bool explicit_size = true;
  if (t.empty()) return fail("missing byte number");
  switch (std::toupper(static_cast<unsigned char>(t[0]))) {
    case 'X':
      a.size = AddrSize::Bit;
      break;
    case 'B':
      a.size = AddrSize::Byte;
      break;
    case 'W':
      a.size = AddrSize::Word;
      break;
    case 'D':
      a.size = AddrSize::DWord;
      break;
    case 'L':
      a.size = AddrSize::LWord;
      break;
    default:
      if (!std::isdigit(static_cast<unsigned char>(t[0])))
        return fail(std::string("unknown size '") + t[0] + "' (expected X, B, W, D or L)");
      explicit_size = false;
      a.size = AddrSize::Bit;
  }
  if (explicit_size) t.remove_prefix(1);
  const auto dot = t.find('.');
  const std::string_view byte_part = t.substr(0, dot);
  if (byte_part.empty()) return fail("missing byte number");
  auto [p, ec] = std::from_chars(byte_part.data(), byte_part.data() + byte_part.size(), a.byte);
  if (ec != std::errc() || p != byte_part.data() + byte_part.size())
    return fail("byte number '" + std::string(byte_part) + "' is not a non-negative integer");
  if (a.size == AddrSize::Bit) {
    if (dot == std::string_view::npos)
      return fail("a bit address needs a bit number (e.g. %IX4.0)");
    const std::string_view bit_part = t.substr(dot + 1);
    unsigned bit = 0;
    auto [q, ec2] = std::from_chars(bit_part.data(), bit_part.data() + bit_part.size(), bit);
    if (bit_part.empty() || ec2 != std::errc() || q != bit_part.data() + bit_part.size())
      return fail("bit number '" + std::string(bit_part) + "' is not an integer");
    if (bit > 7) return fail("bit number " + std::to_string(bit) + " out of range 0..7");
    a.bit = static_cast<std::uint8_t>(bit);
  } else if (dot != std::string_view::npos) {
    return fail("only bit addresses (X) take a bit number");
  }
  return {a, {}};
}

std::optional<AddrSize> addr_size_for(VarType t) {
  switch (t) {
    case VarType::BOOL:
      return AddrSize::Bit;
    case VarType::SINT:
    case VarType::USINT:
    case VarType::BYTE:
      return AddrSize::Byte;
    case VarType::INT:
    case VarType::UINT:
    case VarType::WORD:
      return AddrSize::Word;
    case VarType::DINT:
    case VarType::UDINT:
    case VarType::DWORD:
    case VarType::REAL:
      return AddrSize::DWord;
    case VarType::LINT:
    case VarType::ULINT:
    case VarType::LWORD:
    case VarType::LREAL:
    case VarType::TIME:
      return AddrSize::LWord;
    case VarType::STRING:
      return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace plc::io

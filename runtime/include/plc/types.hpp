// IEC 61131-3 elementary data types as C++ types.
//
// Integer and floating types are plain aliases so FB code reads like ST and
// compiles to the same instructions as hand-written C++. The bit-string types
// (BYTE, WORD, DWORD, LWORD) are distinct types so that reflection can tell a
// WORD (printed 16#047F) from a UINT (printed 1151); they convert implicitly
// to and from their underlying unsigned integer.
#pragma once

#include <chrono>
#include <cstdint>
#include <type_traits>

#include "plc/fixed_string.hpp"

namespace plc {

using BOOL = bool;
using SINT = std::int8_t;
using INT = std::int16_t;
using DINT = std::int32_t;
using LINT = std::int64_t;
using USINT = std::uint8_t;
using UINT = std::uint16_t;
using UDINT = std::uint32_t;
using ULINT = std::uint64_t;
using REAL = float;
using LREAL = double;
// TIME with nanosecond resolution (IEC leaves the resolution to the
// implementation); std::chrono gives literals: t.PT = 20ms.
using TIME = std::chrono::nanoseconds;

// A bit string: an unsigned integer with bit access. Distinct type per width.
template <class U, int Tag>
struct BitString {
  static_assert(std::is_unsigned_v<U>);
  using value_type = U;
  U value{};

  constexpr BitString() = default;
  constexpr BitString(U v) : value(v) {}          // NOLINT: implicit like an IEC literal
  constexpr operator U() const { return value; }  // NOLINT

  [[nodiscard]] constexpr bool bit(unsigned i) const { return (value >> i) & 1U; }
  constexpr void set_bit(unsigned i, bool on) {
    value = on ? U(value | (U(1) << i)) : U(value & ~(U(1) << i));
  }
  constexpr BitString& operator|=(U m) {
    value = U(value | m);
    return *this;
  }
  constexpr BitString& operator&=(U m) {
    value = U(value & m);
    return *this;
  }
  constexpr BitString& operator^=(U m) {
    value = U(value ^ m);
    return *this;
  }
};

using BYTE = BitString<std::uint8_t, 1>;
using WORD = BitString<std::uint16_t, 2>;
using DWORD = BitString<std::uint32_t, 3>;
using LWORD = BitString<std::uint64_t, 4>;

// IEC STRING: fixed capacity, no heap (default length as in CODESYS: 80).
using STRING = FixedString<80>;

// Type tag for the variable registry (debugger, trace, HMI, retain).
enum class VarType : std::uint8_t {
  BOOL,
  SINT,
  INT,
  DINT,
  LINT,
  USINT,
  UINT,
  UDINT,
  ULINT,
  BYTE,
  WORD,
  DWORD,
  LWORD,
  REAL,
  LREAL,
  TIME,
  STRING
};

const char* to_string(VarType t);
// Size in bytes of the value (for STRING: the capacity incl. terminator).
std::size_t size_of(VarType t);

template <class T>
struct VarTypeOf;  // undefined for non-elementary types
template <>
struct VarTypeOf<BOOL> {
  static constexpr VarType value = VarType::BOOL;
};
template <>
struct VarTypeOf<SINT> {
  static constexpr VarType value = VarType::SINT;
};
template <>
struct VarTypeOf<INT> {
  static constexpr VarType value = VarType::INT;
};
template <>
struct VarTypeOf<DINT> {
  static constexpr VarType value = VarType::DINT;
};
template <>
struct VarTypeOf<LINT> {
  static constexpr VarType value = VarType::LINT;
};
template <>
struct VarTypeOf<USINT> {
  static constexpr VarType value = VarType::USINT;
};
template <>
struct VarTypeOf<UINT> {
  static constexpr VarType value = VarType::UINT;
};
template <>
struct VarTypeOf<UDINT> {
  static constexpr VarType value = VarType::UDINT;
};
template <>
struct VarTypeOf<ULINT> {
  static constexpr VarType value = VarType::ULINT;
};
template <>
struct VarTypeOf<BYTE> {
  static constexpr VarType value = VarType::BYTE;
};
template <>
struct VarTypeOf<WORD> {
  static constexpr VarType value = VarType::WORD;
};
template <>
struct VarTypeOf<DWORD> {
  static constexpr VarType value = VarType::DWORD;
};
template <>
struct VarTypeOf<LWORD> {
  static constexpr VarType value = VarType::LWORD;
};
template <>
struct VarTypeOf<REAL> {
  static constexpr VarType value = VarType::REAL;
};
template <>
struct VarTypeOf<LREAL> {
  static constexpr VarType value = VarType::LREAL;
};
template <>
struct VarTypeOf<TIME> {
  static constexpr VarType value = VarType::TIME;
};
template <std::size_t N>
struct VarTypeOf<FixedString<N>> {
  static constexpr VarType value = VarType::STRING;
};

template <class T, class = void>
struct IsElementary : std::false_type {};
template <class T>
struct IsElementary<T, std::void_t<decltype(VarTypeOf<T>::value)>> : std::true_type {};
template <class T>
inline constexpr bool is_elementary_v = IsElementary<T>::value;

}  // namespace plc

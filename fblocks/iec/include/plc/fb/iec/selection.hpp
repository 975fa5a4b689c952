// Selection functions SEL, MAX, MIN, LIMIT, MUX (IEC 61131-3 ed.3 6.6.2.5.12
// Table 32 / ed.2 2.5.1.5.4 Table 27). Functions, not FBs: no state.
//
//   SEL(G, IN0, IN1)      IN0 if G = FALSE, else IN1
//   MAX(IN1, IN2, ...)    largest input (extensible)
//   MIN(IN1, IN2, ...)    smallest input (extensible)
//   LIMIT(MN, IN, MX)     MIN(MAX(IN, MN), MX)
//   MUX(K, IN0, IN1, ...) IN<K> (extensible)
//
// Readings: the inputs of MAX/MIN/MUX/LIMIT share one type (IEC ANY_ELEMENTARY
// overloads have equal input types), enforced by std::common_type with
// same-type checks. MUX with K outside 0..n-1 is an error in IEC with an
// implementation-specific result; here K is clamped to the valid range (no
// exceptions inside a scan). LIMIT with MN > MX returns MX (the formula).
//
// Note: glibc's <sys/param.h> defines MIN/MAX macros; do not include it in
// translation units that use these functions.
#pragma once

#include <array>
#include <type_traits>

#include "plc/types.hpp"

namespace plc::iec {

template <class T>
constexpr T SEL(BOOL G, T IN0, T IN1) {
  return G ? IN1 : IN0;
}

template <class T, class... Ts>
requires(std::is_same_v<T, Ts>&&...) constexpr T MAX(T IN1, Ts... rest) {
  T m = IN1;
  ((m = rest > m ? rest : m), ...);
  return m;
}

template <class T, class... Ts>
requires(std::is_same_v<T, Ts>&&...) constexpr T MIN(T IN1, Ts... rest) {
  T m = IN1;
  ((m = rest < m ? rest : m), ...);
  return m;
}

template <class T>
constexpr T LIMIT(T MN, T IN, T MX) {
  return MIN(MAX(IN, MN), MX);
}

template <class K, class T, class... Ts>
requires(std::is_integral_v<K> && !std::is_same_v<K, bool> &&
         (std::is_same_v<T, Ts> && ...)) constexpr T MUX(K k, T IN0, Ts... rest) {
  const std::array<T, 1 + sizeof...(Ts)> in{IN0, rest...};
  if constexpr (std::is_signed_v<K>) {
    if (k < K{0}) return in.front();
  }
  if (static_cast<std::make_unsigned_t<K>>(k) >= in.size()) return in.back();
  return in[static_cast<std::size_t>(k)];
}

}  // namespace plc::iec

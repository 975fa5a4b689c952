// Typed big-endian and little-endian access to byte buffers (process image,
// telegrams, records). PROFINET and PROFIBUS data are big-endian; DeviceNet is
// little-endian. All functions take the offset in bytes and never read past
// the span (callers check sizes once at bind time; these assert in debug).
#pragma once

#include <bit>
#include <cassert>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>

namespace plc::io {

enum class ByteOrder : std::uint8_t { Big, Little };

namespace detail {
template <class T>
constexpr T byteswap(T v) {
  if constexpr (sizeof(T) == 1) {
    return v;
  } else if constexpr (sizeof(T) == 2) {
    return static_cast<T>(__builtin_bswap16(static_cast<std::uint16_t>(v)));
  } else if constexpr (sizeof(T) == 4) {
    return static_cast<T>(__builtin_bswap32(static_cast<std::uint32_t>(v)));
  } else {
    return static_cast<T>(__builtin_bswap64(static_cast<std::uint64_t>(v)));
  }
}
template <class T>
struct UintOf;
template <>
struct UintOf<float> {
  using type = std::uint32_t;
};
template <>
struct UintOf<double> {
  using type = std::uint64_t;
};
}  // namespace detail

// Reads a T (integral, enum-free, float or double) stored at p in `order`.
template <class T>
inline T load(const std::uint8_t* p, ByteOrder order) {
  if constexpr (std::is_floating_point_v<T>) {
    using U = typename detail::UintOf<T>::type;
    return std::bit_cast<T>(load<U>(p, order));
  } else {
    T v;
    std::memcpy(&v, p, sizeof(T));
    const bool native_big = std::endian::native == std::endian::big;
    if ((order == ByteOrder::Big) != native_big) v = detail::byteswap(v);
    return v;
  }
}

template <class T>
inline void store(std::uint8_t* p, T v, ByteOrder order) {
  if constexpr (std::is_floating_point_v<T>) {
    using U = typename detail::UintOf<T>::type;
    store<U>(p, std::bit_cast<U>(v), order);
  } else {
    const bool native_big = std::endian::native == std::endian::big;
    if ((order == ByteOrder::Big) != native_big) v = detail::byteswap(v);
    std::memcpy(p, &v, sizeof(T));
  }
}

template <class T>
inline T load_be(std::span<const std::uint8_t> b, std::size_t off) {
  assert(off + sizeof(T) <= b.size());
  return load<T>(b.data() + off, ByteOrder::Big);
}
template <class T>
inline T load_le(std::span<const std::uint8_t> b, std::size_t off) {
  assert(off + sizeof(T) <= b.size());
  return load<T>(b.data() + off, ByteOrder::Little);
}
template <class T>
inline void store_be(std::span<std::uint8_t> b, std::size_t off, T v) {
  assert(off + sizeof(T) <= b.size());
  store<T>(b.data() + off, v, ByteOrder::Big);
}
template <class T>
inline void store_le(std::span<std::uint8_t> b, std::size_t off, T v) {
  assert(off + sizeof(T) <= b.size());
  store<T>(b.data() + off, v, ByteOrder::Little);
}

}  // namespace plc::io

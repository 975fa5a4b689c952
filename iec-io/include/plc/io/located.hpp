// A program variable located in the process image (IEC `AT %IX0.0`).
//
//   plc::io::Located<plc::BOOL> start{"%IX0.0"};
//   plc::io::Located<plc::INT>  level{"%IW2"};
//   if (start) level_sp = level * 2;
//
// The address in the code is a default; the cell config's `bind:` can move
// it. At set-up the runtime points it into the image copy of the task that
// runs the program, so reading and writing it costs a load/store plus the
// byte-order conversion of the image (big-endian by default, as on S7).
// Before binding it reads and writes a private scratch value, so a program
// can be unit-tested without a runtime.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "plc/fixed_string.hpp"
#include "plc/io/byte_order.hpp"
#include "plc/types.hpp"

namespace plc::io {

// The type-independent part of a located variable: where it points.
class LocatedBase {
 public:
  explicit LocatedBase(std::string_view address) : address_(address) {}
  LocatedBase(const LocatedBase&) = delete;
  LocatedBase& operator=(const LocatedBase&) = delete;

  [[nodiscard]] std::string_view address() const { return address_.view(); }
  void set_address(std::string_view a) { address_ = a; }
  // Runtime: point at the image byte (and bit) with the image's byte order.
  void bind(std::uint8_t* p, std::uint8_t bit, ByteOrder order) {
    p_ = p;
    bit_ = bit;
    order_ = order;
  }
  [[nodiscard]] bool bound() const { return p_ != scratch_.data(); }

 protected:
  alignas(8) std::array<std::uint8_t, 8> scratch_{};
  std::uint8_t* p_ = scratch_.data();
  std::uint8_t bit_ = 0;
  ByteOrder order_ = ByteOrder::Big;
  FixedString<23> address_;
};

template <class T>
class Located : public LocatedBase {
  static_assert(is_elementary_v<T> && !std::is_same_v<T, STRING>,
                "Located<T> needs an elementary non-STRING type");

 public:
  using value_type = T;
  explicit Located(std::string_view address = {}) : LocatedBase(address) {}

  [[nodiscard]] T get() const {
    if constexpr (std::is_same_v<T, bool>) {
      return (*p_ >> bit_) & 1U;
    } else if constexpr (std::is_same_v<T, TIME>) {
      return TIME(load<std::int64_t>(p_, order_));
    } else if constexpr (sizeof(T) == 1) {
      return static_cast<T>(*p_);
    } else if constexpr (requires { typename T::value_type; }) {
      return T(load<typename T::value_type>(p_, order_));
    } else {
      return load<T>(p_, order_);
    }
  }
  void set(T v) {
    if constexpr (std::is_same_v<T, bool>) {
      *p_ = static_cast<std::uint8_t>(v ? (*p_ | (1U << bit_)) : (*p_ & ~(1U << bit_)));
    } else if constexpr (std::is_same_v<T, TIME>) {
      store<std::int64_t>(p_, v.count(), order_);
    } else if constexpr (sizeof(T) == 1) {
      *p_ = static_cast<std::uint8_t>(v);
    } else if constexpr (requires { typename T::value_type; }) {
      store<typename T::value_type>(p_, v.value, order_);
    } else {
      store<T>(p_, v, order_);
    }
  }
  operator T() const { return get(); }  // NOLINT: reads like a plain variable
  Located& operator=(T v) {
    set(v);
    return *this;
  }
};

template <class T>
struct IsLocated : std::false_type {};
template <class T>
struct IsLocated<Located<T>> : std::true_type {};

}  // namespace plc::io

// Walks an FB's or program's PLC_REFLECT declaration and collects every
// field by path: plain variables (with their native storage), located
// variables (to bind into the image) and device ports (to bind to devices),
// each with its write access: internal state (PLC_INTERNAL, and everything
// below an internal field) is read-only unless its block gives a write
// check (PLC_WRITE_CHECK), see reflect.hpp; and its retain class
// (PLC_RETAIN, PLC_PERSISTENT, inherited the same way).
#pragma once

#include <string>
#include <type_traits>
#include <vector>

#include "plc/io/device_port.hpp"
#include "plc/io/located.hpp"
#include "plc/reflect.hpp"
#include "plc/types.hpp"

namespace plc {

class FieldVisitor {
 public:
  // `seq` is the declaration order across all three lists.
  // How the outside (debugger, init:, HMI) may write a field.
  struct Access {
    bool read_only = false;  // internal state without a write check
    WriteCheck check;        // the block's check of a value before a write
  };
  struct Field {
    std::string path;
    VarType type;
    void* ptr;
    std::size_t seq;
    Access access;
    RetainClass retain = RetainClass::None;
  };
  struct LocatedField {
    std::string path;
    VarType type;
    io::LocatedBase* var;
    std::size_t seq;
    Access access;
    RetainClass retain = RetainClass::None;
  };
  struct PortField {
    std::string path;
    io::DevicePort* port;
    std::size_t seq;
  };

  explicit FieldVisitor(std::string root) : prefix_(std::move(root)) {}

  template <class T>
  void operator()(const char* name, T& f) {
    (*this)(name, f, FieldMeta{});
  }

  template <class T>
  void operator()(const char* name, T& f, const FieldMeta& meta) {
    // Internal-ness is inherited: below an internal field every field is
    // read-only, whatever its own class declares about it.
    Access access;
    if (inside_internal_) {
      access.read_only = true;
    } else {
      access.read_only = meta.internal && meta.check == nullptr;
      access.check = {meta.check, meta.owner};
    }
    // The retain class is inherited too: an FB instance declared RETAIN
    // keeps all of itself; inner declarations count below an unclassed field.
    const RetainClass retain = inside_retain_ != RetainClass::None ? inside_retain_ : meta.retain;
    if constexpr (io::IsLocated<T>::value) {
      located.push_back(
          {path(name), VarTypeOf<typename T::value_type>::value, &f, seq_++, access, retain});
    } else if constexpr (std::is_same_v<T, io::DevicePort>) {
      ports.push_back({path(name), &f, seq_++});
    } else if constexpr (is_elementary_v<T>) {
      fields.push_back({path(name), VarTypeOf<T>::value, &f, seq_++, access, retain});
    } else if constexpr (std::is_enum_v<T>) {
      using U = std::underlying_type_t<T>;
      static_assert(is_elementary_v<U>, "reflected enums need an integer underlying type");
      fields.push_back({path(name), VarTypeOf<U>::value, &f, seq_++, access, retain});
    } else if constexpr (IsStdArray<T>::value) {
      const std::string base = name;
      for (std::size_t i = 0; i < f.size(); ++i) {
        const std::string item = base + "[" + std::to_string(i) + "]";
        (*this)(item.c_str(), f[i], meta);
      }
    } else if constexpr (HasReflect<T, FieldVisitor>::value) {
      const std::size_t keep = prefix_.size();
      const bool keep_internal = inside_internal_;
      const RetainClass keep_retain = inside_retain_;
      prefix_ += '.';
      prefix_ += name;
      inside_internal_ = inside_internal_ || meta.internal;
      inside_retain_ = retain;
      f.reflect(*this);
      inside_internal_ = keep_internal;
      inside_retain_ = keep_retain;
      prefix_.resize(keep);
    } else {
      static_assert(sizeof(T) == 0,
                    "PLC_REFLECT lists a field of a type that cannot be reflected: use an IEC "
                    "elementary type, an enum, an FB with PLC_REFLECT, a std::array of those, "
                    "a Located<T> or a DevicePort");
    }
  }

  std::vector<Field> fields;
  std::vector<LocatedField> located;
  std::vector<PortField> ports;

 private:
  std::string path(const char* name) const { return prefix_ + "." + name; }
  std::string prefix_;
  std::size_t seq_ = 0;
  bool inside_internal_ = false;
  RetainClass inside_retain_ = RetainClass::None;
};

// Collects the fields of any reflected object under `root` (tests, tools).
template <class T>
FieldVisitor collect_fields(const std::string& root, T& obj) {
  FieldVisitor v(root);
  obj.reflect(v);
  return v;
}

}  // namespace plc

// Walks an FB's or program's PLC_REFLECT declaration and collects every
// field by path: plain variables (with their native storage), located
// variables (to bind into the image) and device ports (to bind to devices).
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
  struct Field {
    std::string path;
    VarType type;
    void* ptr;
    std::size_t seq;
  };
  struct LocatedField {
    std::string path;
    VarType type;
    io::LocatedBase* var;
    std::size_t seq;
  };
  struct PortField {
    std::string path;
    io::DevicePort* port;
    std::size_t seq;
  };

  explicit FieldVisitor(std::string root) : prefix_(std::move(root)) {}

  template <class T>
  void operator()(const char* name, T& f) {
    if constexpr (io::IsLocated<T>::value) {
      located.push_back({path(name), VarTypeOf<typename T::value_type>::value, &f, seq_++});
    } else if constexpr (std::is_same_v<T, io::DevicePort>) {
      ports.push_back({path(name), &f, seq_++});
    } else if constexpr (is_elementary_v<T>) {
      fields.push_back({path(name), VarTypeOf<T>::value, &f, seq_++});
    } else if constexpr (std::is_enum_v<T>) {
      using U = std::underlying_type_t<T>;
      static_assert(is_elementary_v<U>, "reflected enums need an integer underlying type");
      fields.push_back({path(name), VarTypeOf<U>::value, &f, seq_++});
    } else if constexpr (IsStdArray<T>::value) {
      const std::string base = name;
      for (std::size_t i = 0; i < f.size(); ++i) {
        const std::string item = base + "[" + std::to_string(i) + "]";
        (*this)(item.c_str(), f[i]);
      }
    } else if constexpr (HasReflect<T, FieldVisitor>::value) {
      const std::size_t keep = prefix_.size();
      prefix_ += '.';
      prefix_ += name;
      f.reflect(*this);
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
};

// Collects the fields of any reflected object under `root` (tests, tools).
template <class T>
FieldVisitor collect_fields(const std::string& root, T& obj) {
  FieldVisitor v(root);
  obj.reflect(v);
  return v;
}

}  // namespace plc

#include "plc/var_registry.hpp"

#include <cstring>

#include "plc/iec_literal.hpp"

namespace plc {

void VarRegistry::add(VarInfo v) {
  index_.emplace(v.path, vars_.size());
  vars_.push_back(std::move(v));
}

VarInfo plain_var_info(const FieldVisitor::Field& f, int task) {
  VarInfo v;
  v.path = f.path;
  v.type = f.type;
  v.ptr = f.ptr;
  v.task = task;
  v.read_only = f.access.read_only;
  v.check = f.access.check;
  v.retain = f.retain;
  return v;
}

void VarRegistry::replace_prefix(const std::string& prefix, std::vector<VarInfo> vars) {
  std::vector<VarInfo> next;
  next.reserve(vars_.size() + vars.size());
  bool placed = false;
  for (VarInfo& v : vars_) {
    if (v.path.compare(0, prefix.size(), prefix) != 0) {
      next.push_back(std::move(v));
    } else if (!placed) {
      for (VarInfo& n : vars) next.push_back(std::move(n));
      placed = true;
    }
  }
  if (!placed)
    for (VarInfo& n : vars) next.push_back(std::move(n));
  vars_ = std::move(next);
  index_.clear();
  for (std::size_t i = 0; i < vars_.size(); ++i) index_.emplace(vars_[i].path, i);
}

const VarInfo* VarRegistry::find(std::string_view path) const {
  auto it = index_.find(std::string(path));
  return it == index_.end() ? nullptr : &vars_[it->second];
}

namespace {

template <class U>
void load_native(const std::uint8_t* p, io::ByteOrder o, void* out) {
  const U v = io::load<U>(p, o);
  std::memcpy(out, &v, sizeof v);
}
template <class U>
void store_native(std::uint8_t* p, io::ByteOrder o, const void* in) {
  U v;
  std::memcpy(&v, in, sizeof v);
  io::store<U>(p, v, o);
}

}  // namespace

void VarRegistry::read(const VarInfo& v, void* out) {
  if (!v.address) {
    if (v.type == VarType::STRING) {
      *static_cast<STRING*>(out) = *static_cast<const STRING*>(v.ptr);
    } else {
      std::memcpy(out, v.ptr, size_of(v.type));
    }
    return;
  }
  const std::uint8_t* p = v.image_ptr;
  switch (size_of(v.type)) {
    case 1:
      if (v.type == VarType::BOOL) {
        *static_cast<bool*>(out) = (*p >> v.address->bit) & 1U;
      } else {
        std::memcpy(out, p, 1);
      }
      break;
    case 2:
      load_native<std::uint16_t>(p, v.order, out);
      break;
    case 4:
      load_native<std::uint32_t>(p, v.order, out);
      break;
    case 8:
      load_native<std::uint64_t>(p, v.order, out);
      break;
    default:
      break;
  }
}

void VarRegistry::write(const VarInfo& v, const void* in) {
  if (!v.address) {
    if (v.type == VarType::STRING) {
      *static_cast<STRING*>(v.ptr) = *static_cast<const STRING*>(in);
    } else {
      std::memcpy(v.ptr, in, size_of(v.type));
    }
    return;
  }
  std::uint8_t* p = v.image_ptr;
  switch (size_of(v.type)) {
    case 1:
      if (v.type == VarType::BOOL) {
        const bool b = *static_cast<const bool*>(in);
        const auto m = static_cast<std::uint8_t>(1U << v.address->bit);
        *p = static_cast<std::uint8_t>(b ? (*p | m) : (*p & ~m));
      } else {
        std::memcpy(p, in, 1);
      }
      break;
    case 2:
      store_native<std::uint16_t>(p, v.order, in);
      break;
    case 4:
      store_native<std::uint32_t>(p, v.order, in);
      break;
    case 8:
      store_native<std::uint64_t>(p, v.order, in);
      break;
    default:
      break;
  }
}

std::string VarRegistry::format(const VarInfo& v) {
  alignas(8) unsigned char buf[sizeof(STRING)];
  if (v.type == VarType::STRING) {
    auto* s = new (buf) STRING();
    read(v, s);
    return format_value(v.type, s);
  }
  read(v, buf);
  return format_value(v.type, buf);
}

std::string VarRegistry::check_write(const VarInfo& v, const void* value) {
  if (v.read_only)
    return "read-only: internal state of its function block (print, watch, trace and break on "
           "it; only the block itself changes it)";
  if (v.check) {
    const std::string why = v.check(value);
    if (!why.empty()) return "refused by its function block: " + why;
  }
  return {};
}

std::string VarRegistry::write_text(const VarInfo& v, std::string_view text) {
  if (v.read_only) return check_write(v, nullptr);  // whatever the value
  alignas(8) unsigned char buf[sizeof(STRING)];
  void* tmp = buf;
  if (v.type == VarType::STRING) tmp = new (buf) STRING();
  std::string err = parse_value(v.type, text, tmp);
  if (err.empty()) err = check_write(v, tmp);
  if (err.empty()) write(v, tmp);
  return err;
}

}  // namespace plc

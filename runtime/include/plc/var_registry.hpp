// The variable registry: every program variable and every FB field by path
// (e.g. `Main.conveyor.t1.ET`) with its type, and for located variables
// their IEC address. The debugger, trace, HMI bridge and retain all reach
// variables through it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "plc/field_visitor.hpp"
#include "plc/io/byte_order.hpp"
#include "plc/io/iec_address.hpp"
#include "plc/reflect.hpp"
#include "plc/types.hpp"

namespace plc {

struct VarInfo {
  std::string path;
  VarType type = VarType::BOOL;
  // A plain variable: native storage inside its program object.
  void* ptr = nullptr;
  // A located variable: lives in the image copy of its task.
  std::optional<io::IecAddress> address;
  std::uint8_t* image_ptr = nullptr;
  io::ByteOrder order = io::ByteOrder::Big;
  int task = -1;  // index of the task whose programs own it (-1: none)
  // Write access from outside the programs (reflect.hpp): internal state of
  // a block is read-only; a block's write check vets every value first.
  bool read_only = false;
  WriteCheck check;
  // Kept over restarts (PLC_RETAIN / PLC_PERSISTENT, runtime/…/retain/).
  RetainClass retain = RetainClass::None;
};

// The registry entry of a plain (not located) field of a program run by
// task `task`.
VarInfo plain_var_info(const FieldVisitor::Field& f, int task);

class VarRegistry {
 public:
  void add(VarInfo v);
  [[nodiscard]] const VarInfo* find(std::string_view path) const;
  [[nodiscard]] const std::vector<VarInfo>& all() const { return vars_; }
  // Online change: the variables under `prefix` ("Main.") become `vars`, in
  // the place the old ones had. Invalidates VarInfo pointers and copies.
  void replace_prefix(const std::string& prefix, std::vector<VarInfo> vars);

  // Copies the value into/out of native storage of size_of(v.type) bytes
  // (for located variables this converts from/to the image byte order).
  static void read(const VarInfo& v, void* out);
  static void write(const VarInfo& v, const void* in);
  // IEC notation of the current value (TRUE, 16#047F, T#1s500ms, ...).
  static std::string format(const VarInfo& v);
  // The write policy for writes from outside the programs (debugger write
  // and force, config init:, the HMI): whether `value` (native storage of
  // v.type) may be written into v. "" if so, else why not. read() and
  // write() do not ask: the runtime's own restores (recording snapshots,
  // goto) put internal state back on purpose.
  static std::string check_write(const VarInfo& v, const void* value);
  // Parses `text`, applies check_write() and writes it (a write from
  // outside); returns an error message or "".
  static std::string write_text(const VarInfo& v, std::string_view text);

 private:
  std::vector<VarInfo> vars_;
  std::unordered_map<std::string, std::size_t> index_;
};

}  // namespace plc

#include "plc/debug/condition.hpp"

#include <algorithm>
#include <cstring>

namespace plc::debug {

namespace {

template <class T>
T load(const unsigned char* buf) {
  T x;
  std::memcpy(&x, buf, sizeof x);
  return x;
}

}  // namespace

Value read_value(const VarInfo& v) {
  alignas(8) unsigned char buf[16] = {};
  Value out;
  if (v.type == VarType::STRING) return out;  // strings compare as 0
  VarRegistry::read(v, buf);
  switch (v.type) {
    case VarType::BOOL:
      out.i = load<bool>(buf) ? 1 : 0;
      break;
    case VarType::SINT:
      out.i = load<std::int8_t>(buf);
      break;
    case VarType::INT:
      out.i = load<std::int16_t>(buf);
      break;
    case VarType::DINT:
      out.i = load<std::int32_t>(buf);
      break;
    case VarType::LINT:
    case VarType::TIME:
      out.i = load<std::int64_t>(buf);
      break;
    case VarType::USINT:
    case VarType::BYTE:
      out.i = load<std::uint8_t>(buf);
      break;
    case VarType::UINT:
    case VarType::WORD:
      out.i = load<std::uint16_t>(buf);
      break;
    case VarType::UDINT:
    case VarType::DWORD:
      out.i = load<std::uint32_t>(buf);
      break;
    case VarType::ULINT:
    case VarType::LWORD:
      // The bit pattern as a LINT (two's complement): values from 2^63 up
      // read as negative numbers, as a PLC's LINT view of the same 64 bits.
      out.i = static_cast<std::int64_t>(load<std::uint64_t>(buf));
      break;
    case VarType::REAL:
      out.real = true;
      out.d = load<float>(buf);
      break;
    case VarType::LREAL:
      out.real = true;
      out.d = load<double>(buf);
      break;
    case VarType::STRING:
      break;
  }
  return out;
}

namespace {

VarType type_of(io::AddrSize s) {
  static const VarType types[] = {VarType::BOOL, VarType::BYTE, VarType::WORD, VarType::DWORD,
                                  VarType::LWORD};
  return types[static_cast<int>(s)];
}

}  // namespace

std::optional<Condition> Condition::compile(std::string_view text, const VarRegistry& vars,
                                            io::ProcessImage& global, io::ByteOrder order,
                                            std::string& error) {
  Condition c;
  c.text_ = std::string(text);
  // Each name becomes an operand; the lookup errors are the parser's.
  auto resolve = [&](const std::string& name, std::string& why) -> std::optional<std::uint16_t> {
    ConditionOperand o;
    if (name[0] == '%') {
      auto r = io::parse_iec_address(name);
      if (!r.address) {
        why = r.error;
        return std::nullopt;
      }
      if (!global.contains(*r.address)) {
        why = name + " lies outside the image";
        return std::nullopt;
      }
      o.address = *r.address;
    } else {
      const VarInfo* v = vars.find(name);
      if (!v) {
        why = "unknown variable '" + name + "'";
        return std::nullopt;
      }
      if (v->type == VarType::STRING) {
        why = "'" + name + "' is a STRING; conditions compare numbers";
        return std::nullopt;
      }
      o.path = name;
    }
    c.operands_.push_back(std::move(o));
    return static_cast<std::uint16_t>(c.operands_.size() - 1);
  };
  auto code = compile_condition(text, resolve, error);
  if (!code) return std::nullopt;
  c.code_ = std::move(*code);
  if (!c.bind_operands(vars, global, order, error)) return std::nullopt;
  return c;
}

std::optional<Condition> Condition::bind(ConditionCode code, std::vector<ConditionOperand> operands,
                                         const VarRegistry& vars, io::ProcessImage& global,
                                         io::ByteOrder order, std::string& error) {
  error = validate(code, operands.size());
  if (!error.empty()) return std::nullopt;
  Condition c;
  c.code_ = std::move(code);
  c.operands_ = std::move(operands);
  if (!c.bind_operands(vars, global, order, error)) return std::nullopt;
  c.text_ = to_text(c.code_, [&c](std::uint16_t i) {
    const ConditionOperand& o = c.operands_[i];
    return o.address ? o.address->to_string() : o.path;
  });
  return c;
}

std::optional<Condition> Condition::rebind(const VarRegistry& vars, io::ProcessImage& global,
                                           io::ByteOrder order, std::string& error) const {
  Condition c;
  c.text_ = text_;
  c.code_ = code_;
  c.operands_ = operands_;
  if (!c.bind_operands(vars, global, order, error)) return std::nullopt;
  return c;
}

bool Condition::bind_operands(const VarRegistry& vars, io::ProcessImage& global,
                              io::ByteOrder order, std::string& error) {
  vars_.clear();
  task_ = -1;
  for (const ConditionOperand& o : operands_) {
    if (o.address) {
      if (!global.contains(*o.address)) {
        error = o.address->to_string() + " lies outside the image";
        return false;
      }
      VarInfo v;
      v.path = o.address->to_string();
      v.address = *o.address;
      v.image_ptr = global.at(*o.address);
      v.order = order;
      v.type = type_of(o.address->size);
      vars_.push_back(v);
      continue;
    }
    const VarInfo* v = vars.find(o.path);
    if (!v) {
      error = "unknown variable '" + o.path + "'";
      return false;
    }
    if (v->type == VarType::STRING) {
      error = "'" + o.path + "' is a STRING; conditions compare numbers";
      return false;
    }
    if (task_ < 0) task_ = v->task;
    vars_.push_back(*v);
  }
  return true;
}

std::vector<const VarInfo*> Condition::variables() const {
  std::vector<const VarInfo*> out;
  for (const VarInfo& v : vars_) out.push_back(&v);
  return out;
}

bool Condition::reads_global() const {
  return std::any_of(vars_.begin(), vars_.end(), [](const VarInfo& v) { return v.task < 0; });
}

Value Condition::evaluate() const {
  return debug::evaluate(code_, [this](std::uint16_t i) { return read_value(vars_[i]); });
}

}  // namespace plc::debug

#include "plc/hmi/host_commands.hpp"

#include <cstring>

namespace plc::hmi {

namespace {

using ipc::Reason;
using ipc::Verb;
using ipc::WireOperand;

struct Refusal {
  Reason reason;
  std::string why;
};

// An operand as plcrun's layout knows it; a refusal otherwise.
std::optional<HostTarget> target_of(const WireOperand& o, const ipc::CellLayout& l,
                                    Refusal& refusal) {
  HostTarget t;
  if (o.kind == WireOperand::Var) {
    if (o.area || o.size || o.bit) {
      refusal = {Reason::Malformed, "a variable operand with address fields set"};
      return std::nullopt;
    }
    if (o.value >= l.vars.size()) {
      refusal = {Reason::BadOperand, "variable index " + std::to_string(o.value) +
                                         " beyond the cell's " + std::to_string(l.vars.size())};
      return std::nullopt;
    }
    t.var = o.value;
    return t;
  }
  if (o.kind == WireOperand::Address) {
    if (o.area > std::uint8_t(io::Area::Memory) || o.size > std::uint8_t(io::AddrSize::LWord) ||
        o.bit > 7 || (o.size != std::uint8_t(io::AddrSize::Bit) && o.bit != 0)) {
      refusal = {Reason::Malformed, "an address operand out of range"};
      return std::nullopt;
    }
    const io::IecAddress a{io::Area(o.area), io::AddrSize(o.size), o.value, o.bit};
    if (!l.inside_image(a)) {
      refusal = {Reason::BadOperand, a.to_string() + " lies outside the image"};
      return std::nullopt;
    }
    t.address = a;
    return t;
  }
  refusal = {Reason::Malformed, "operand kind " + std::to_string(o.kind)};
  return std::nullopt;
}

RecordCheck refuse(Reason r, std::string why) {
  RecordCheck c;
  c.reason = r;
  c.why = std::move(why);
  return c;
}

bool stopping(Verb v) {
  return v == Verb::Pause || v == Verb::Step || v == Verb::Continue || v == Verb::Break ||
         v == Verb::Delete || v == Verb::DeleteAll;
}

}  // namespace

RecordCheck check_record(const ipc::CommandRecord& r, const ipc::CellLayout& l,
                         std::uint64_t generation, bool stop_commands) {
  if (r.verb == 0 || r.verb >= ipc::kVerbs)
    return refuse(Reason::Malformed, "verb " + std::to_string(r.verb));
  const Verb verb = Verb(r.verb);
  if (r.restore > 1) return refuse(Reason::Malformed, "restore flag " + std::to_string(r.restore));
  if (r.generation != generation)
    return refuse(Reason::Stale, "made for generation " + std::to_string(r.generation) +
                                     " of the cell, which is now at " + std::to_string(generation) +
                                     " (rebuilt since)");
  if (stopping(verb) && !stop_commands)
    return refuse(Reason::NoStops, "not allowed: the cell's hmi: stop_commands is false");
  HostCommand c;
  c.verb = verb;
  c.token = r.token;
  c.restore = r.restore != 0;
  c.count = r.count;
  Refusal refusal{Reason::Ok, ""};
  switch (verb) {
    case Verb::Write:
    case Verb::Force:
    case Verb::Unforce: {
      if (r.target.kind != WireOperand::Var)
        return refuse(verb == Verb::Write ? Reason::NotWritable : Reason::NotForceable,
                      "not a variable of the cell's layout");
      auto t = target_of(r.target, l, refusal);
      if (!t) return refuse(refusal.reason, refusal.why);
      const ipc::CellLayout::Var& v = l.vars[*t->var];
      if (verb == Verb::Write && !v.writable)
        return refuse(Reason::NotWritable, v.path + " is not writable from the HMI");
      if (verb != Verb::Write && !v.forceable)
        return refuse(Reason::NotForceable, v.path + " is not forceable from the HMI");
      c.target = *t;
      std::memcpy(c.value, r.value, sizeof c.value);
      break;
    }
    case Verb::Read: {
      if (r.n_operands < 1 || r.n_operands > ipc::kMaxReadOperands)
        return refuse(Reason::Malformed, "read of " + std::to_string(r.n_operands) +
                                             " variables (1 to " +
                                             std::to_string(ipc::kMaxReadOperands) + ")");
      for (std::size_t i = 0; i < r.n_operands; ++i) {
        auto t = target_of(r.operands[i], l, refusal);
        if (!t) return refuse(refusal.reason, refusal.why);
        c.operands.push_back(*t);
      }
      break;
    }
    case Verb::Step:
      if (r.count < 1 || r.count > ipc::kMaxStep)
        return refuse(Reason::Malformed, "step of " + std::to_string(r.count) + " scans");
      break;
    case Verb::Delete:
      if (r.count < 1 || r.count > 0x7fffffff)
        return refuse(Reason::Malformed, "breakpoint id " + std::to_string(r.count));
      break;
    case Verb::Break: {
      if (r.count < 1 || r.count > 0xffffffff)
        return refuse(Reason::Malformed, "hits " + std::to_string(r.count));
      if (r.n_instrs > debug::ConditionCode::kMaxInstrs ||
          r.n_consts > debug::ConditionCode::kMaxConsts || r.n_operands > ipc::kMaxCodeOperands)
        return refuse(Reason::Malformed, "condition code beyond its arrays");
      for (std::size_t i = 0; i < r.n_operands; ++i) {
        auto t = target_of(r.operands[i], l, refusal);
        if (!t) return refuse(refusal.reason, refusal.why);
        if (t->var && l.vars[*t->var].type == VarType::STRING)
          return refuse(Reason::BadCode, l.vars[*t->var].path + " is a STRING");
        c.operands.push_back(*t);
      }
      for (std::size_t i = 0; i < r.n_instrs; ++i) {
        if (r.instrs[i].pad) return refuse(Reason::Malformed, "instruction padding set");
        c.code.code.push_back({debug::ConditionCode::Op(r.instrs[i].op), r.instrs[i].index});
      }
      for (std::size_t i = 0; i < r.n_consts; ++i) {
        const ipc::WireConst& k = r.consts[i];
        if (k.real > 1) return refuse(Reason::Malformed, "constant kind");
        debug::Value v;
        v.real = k.real != 0;
        if (v.real)
          std::memcpy(&v.d, &k.bits, sizeof v.d);
        else
          v.i = static_cast<std::int64_t>(k.bits);
        c.code.consts.push_back(v);
      }
      if (const std::string why = debug::validate(c.code, c.operands.size()); !why.empty())
        return refuse(Reason::BadCode, "condition code: " + why);
      break;
    }
    default:
      break;
  }
  RecordCheck out;
  out.command = std::move(c);
  return out;
}

}  // namespace plc::hmi

// The compiled form of a condition (plc/debug/condition.hpp), apart from any
// runtime: postfix code over constants and numbered operands. The parser
// asks a resolver what each name is, so it runs against the runtime's
// registry (the debugger) as well as against a cell description that holds
// no memory at all (the HMI bridge's own process, hmi-bridge/plchmi/), which
// then hands plcrun the code instead of the text.
//
// Code that did not come from this parser (from another process) is checked
// by validate() before anything evaluates it: op codes, constant and operand
// indices, the operand stack's depth at every instruction, its length. Code
// that validates evaluates without reading outside its arrays and within
// the fixed operand stack.
//
// Arithmetic, defined for every input (no trap, no undefined behaviour):
// * Integers of every type (BOOL, ANY_INT, ANY_BIT, TIME in ns) are taken as
//   LINT and computed in 64-bit two's complement that wraps around, as a
//   PLC's LINT does: 9223372036854775807 + 1 = -9223372036854775808.
//   ULINT/LWORD values from 2^63 up read as their (negative) LINT pattern.
// * Division and MOD by zero give 0 (REAL too), so a condition such as
//   `a / b > 3` is simply false while b = 0 instead of stopping the scan;
//   LINT_MIN / -1 wraps to LINT_MIN and LINT_MIN MOD -1 is 0.
// * REAL/LREAL follow IEEE 754: overflow gives +-inf, and NaN compares
//   unordered (=, <, <=, >, >= are FALSE, <> is TRUE).
// * An integer compared with a real is compared exactly (no rounding of
//   the integer to double).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plc::debug {

struct Value {
  bool real = false;
  std::int64_t i = 0;
  double d = 0;
  [[nodiscard]] double as_real() const { return real ? d : double(i); }
  [[nodiscard]] bool truthy() const { return real ? d != 0 : i != 0; }
  friend bool operator==(const Value&, const Value&) = default;
};

struct ConditionCode {
  // The op codes' values are part of the HMI's shared-memory record format
  // (hmi-bridge/include/plc/hmi/ipc/records.hpp): append, never reorder.
  enum class Op : std::uint8_t {
    Const,
    Var,
    Add,
    Sub,
    Mul,
    Div,
    Mod,
    Neg,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    And,
    Or,
    Xor,
    Not
  };
  static constexpr std::uint8_t kOps = std::uint8_t(Op::Not) + 1;
  struct Instr {
    Op op = Op::Const;
    std::uint16_t index = 0;  // Const: into consts; Var: an operand number
    friend bool operator==(const Instr&, const Instr&) = default;
  };

  // People nest a handful of levels; 64 keeps the recursive-descent parser
  // far inside any thread's stack, also under sanitizers.
  static constexpr int kMaxNesting = 64;
  // The evaluator's fixed operand stack (no allocation while evaluating).
  static constexpr int kMaxStack = 32;
  // Bounds on code from outside (and on what the parser produces).
  static constexpr std::size_t kMaxInstrs = 256;
  static constexpr std::size_t kMaxConsts = 64;
  static constexpr std::size_t kMaxOperands = 64;

  std::vector<Instr> code;
  std::vector<Value> consts;
  friend bool operator==(const ConditionCode&, const ConditionCode&) = default;
};

// What a name in a condition is: an operand number the caller chose (the
// code refers to it), or nullopt with the reason in `error` ("unknown
// variable 'X'"). Called once per occurrence of a name.
using ConditionResolver =
    std::function<std::optional<std::uint16_t>(const std::string& name, std::string& error)>;

// Compiles `text` (ST syntax, condition.hpp); nullopt and `error` (which
// names the unknown variable or the column of the syntax error) on failure.
std::optional<ConditionCode> compile_condition(std::string_view text,
                                               const ConditionResolver& resolve,
                                               std::string& error);

// "" when `c` is safe to evaluate with `operands` operands: every op code
// known, every index in range, the stack never below what an op takes nor
// above kMaxStack, exactly one value left, within the bounds above; else
// what is wrong.
std::string validate(const ConditionCode& c, std::size_t operands);

// The condition as text, from its code: what the console lists for a
// breakpoint that came as code. Operands are named by `name_of`; no more
// parentheses than the precedence needs. Compiling the text again gives
// the same code (for code the parser made).
std::string to_text(const ConditionCode& c,
                    const std::function<std::string(std::uint16_t)>& name_of);

// One binary operation (Add .. Xor) as the evaluator applies it.
Value apply_binary(ConditionCode::Op op, const Value& a, const Value& b);
Value apply_unary(ConditionCode::Op op, const Value& a);

// Evaluates validated code; `read(operand)` gives an operand's value. No
// allocation.
template <class Read>
Value evaluate(const ConditionCode& c, Read&& read) {
  std::array<Value, ConditionCode::kMaxStack> st;
  int sp = 0;
  for (const ConditionCode::Instr& in : c.code) {
    switch (in.op) {
      case ConditionCode::Op::Const:
        st[std::size_t(sp++)] = c.consts[in.index];
        break;
      case ConditionCode::Op::Var:
        st[std::size_t(sp++)] = read(in.index);
        break;
      case ConditionCode::Op::Neg:
      case ConditionCode::Op::Not:
        st[std::size_t(sp - 1)] = apply_unary(in.op, st[std::size_t(sp - 1)]);
        break;
      default:
        --sp;
        st[std::size_t(sp - 1)] = apply_binary(in.op, st[std::size_t(sp - 1)], st[std::size_t(sp)]);
    }
  }
  return sp > 0 ? st[0] : Value{};
}

}  // namespace plc::debug

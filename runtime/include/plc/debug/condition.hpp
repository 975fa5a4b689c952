// Conditions over variables, for breakpoints and trace triggers:
//
//   Main.weigh.State = 4 AND Main.axis.ActPosition > 1000
//   NOT Tank.enable OR (Tank.level >= 16#5000 AND Tank.hold.ET > T#1s)
//   %IX0.3 AND %QW0 <> 0
//
// ST syntax: OR, XOR, AND (&), NOT; = <> < <= > >=; + - * / MOD; unary -;
// parentheses; literals TRUE/FALSE, integers (16#, 2#, 8#), reals, durations
// (T#...). Operands are variable paths from the registry or IEC addresses
// (read from the global image). Parsed and compiled once into postfix code;
// evaluation reads the variables and never allocates.
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
// * At most kMaxNesting levels of parentheses, NOT and unary '-', and
//   kMaxOperands operands pending at once; deeper conditions are refused
//   when compiled, naming the column.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "plc/io/process_image.hpp"
#include "plc/var_registry.hpp"

namespace plc::debug {

struct Value {
  bool real = false;
  std::int64_t i = 0;
  double d = 0;
  [[nodiscard]] double as_real() const { return real ? d : double(i); }
  [[nodiscard]] bool truthy() const { return real ? d != 0 : i != 0; }
};

// Reads a registry variable as a Value (BOOL -> 0/1, TIME -> ns).
Value read_value(const VarInfo& v);

class Condition {
 public:
  // People nest a handful of levels; 64 keeps the recursive-descent parser
  // far inside any thread's stack, also under sanitizers.
  static constexpr int kMaxNesting = 64;
  // The evaluator's fixed operand stack (no allocation while evaluating).
  static constexpr int kMaxOperands = 32;

  // Compiles `text`; on failure returns nullopt and sets `error` (which names
  // the unknown variable or the position of the syntax error).
  static std::optional<Condition> compile(std::string_view text, const VarRegistry& vars,
                                          io::ProcessImage& global, io::ByteOrder order,
                                          std::string& error);

  [[nodiscard]] Value evaluate() const;
  [[nodiscard]] bool holds() const { return evaluate().truthy(); }
  [[nodiscard]] const std::string& text() const { return text_; }
  // The task that owns the first variable in the condition (-1: none, e.g.
  // only addresses): the condition is evaluated after that task's scans.
  [[nodiscard]] int task() const { return task_; }
  // The variables it reads (program variables, and addresses, which belong
  // to no task: VarInfo::task -1).
  [[nodiscard]] std::vector<const VarInfo*> variables() const;
  // Whether it reads the global image (an address operand): in real time it
  // is then evaluated under the image lock.
  [[nodiscard]] bool reads_global() const;

 private:
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
  struct Instr {
    Op op;
    std::uint32_t index;  // Const: into consts_; Var: into vars_
  };
  std::string text_;
  std::vector<Instr> code_;
  std::vector<Value> consts_;
  std::vector<VarInfo> vars_;  // copies (address operands point into the global image)
  int task_ = -1;

  friend class ConditionParser;
};

}  // namespace plc::debug

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

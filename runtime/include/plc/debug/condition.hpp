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
// Parsed and compiled by plc/debug/condition_code.hpp, which holds the
// arithmetic's rules (defined for every input: wrap-around LINT, division
// by zero gives 0, IEEE 754 reals, exact integer/real comparison). A
// Condition binds that code to the runtime's variables; code compiled
// elsewhere (the HMI bridge's process, against a cell description) is
// validated and bound the same way, and a rebuilt runtime rebinds it by
// path and address, never by parsing its text again.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "plc/debug/condition_code.hpp"
#include "plc/io/process_image.hpp"
#include "plc/var_registry.hpp"

namespace plc::debug {

// What an operand of the code is: a registry variable by path, or an IEC
// address (read from the global image).
struct ConditionOperand {
  std::string path;                       // "" for an address
  std::optional<io::IecAddress> address;  // set for an address
};

// Reads a registry variable as a Value (BOOL -> 0/1, TIME -> ns).
Value read_value(const VarInfo& v);

class Condition {
 public:
  static constexpr int kMaxNesting = ConditionCode::kMaxNesting;
  // The evaluator's fixed operand stack (no allocation while evaluating).
  static constexpr int kMaxOperands = ConditionCode::kMaxStack;

  // Compiles `text`; on failure returns nullopt and sets `error` (which names
  // the unknown variable or the position of the syntax error).
  static std::optional<Condition> compile(std::string_view text, const VarRegistry& vars,
                                          io::ProcessImage& global, io::ByteOrder order,
                                          std::string& error);
  // Code compiled elsewhere: validated (condition_code.hpp validate()), each
  // operand looked up (a path in the registry, an address inside the image;
  // STRING refused), then bound. Its text is made from the code. nullopt
  // and `error` when it cannot be.
  static std::optional<Condition> bind(ConditionCode code, std::vector<ConditionOperand> operands,
                                       const VarRegistry& vars, io::ProcessImage& global,
                                       io::ByteOrder order, std::string& error);
  // The same condition on another registry and image (a rebuilt runtime, an
  // online change's new build), by its operands' paths and addresses.
  [[nodiscard]] std::optional<Condition> rebind(const VarRegistry& vars, io::ProcessImage& global,
                                                io::ByteOrder order, std::string& error) const;

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
  [[nodiscard]] const ConditionCode& code() const { return code_; }
  [[nodiscard]] const std::vector<ConditionOperand>& operands() const { return operands_; }

 private:
  // Looks every operand up and fills vars_ and task_.
  bool bind_operands(const VarRegistry& vars, io::ProcessImage& global, io::ByteOrder order,
                     std::string& error);

  std::string text_;
  ConditionCode code_;
  std::vector<ConditionOperand> operands_;
  std::vector<VarInfo> vars_;  // per operand (address operands point into the global image)
  int task_ = -1;
};

}  // namespace plc::debug

// The records of the command ring (plchmi -> plcrun) and the reply ring
// (plcrun -> plchmi). Binary and of fixed size; nothing in a command is
// text: a variable is its index in the cell layout (or an IEC address as
// numbers), a value is already the bytes of its type (plchmi parsed the
// literal), a breakpoint condition is postfix code over numbered operands
// (plchmi compiled it, plc/debug/condition_code.hpp). plcrun checks every
// field (host_commands.hpp) and refuses with a Reason; replies may carry
// text, since plcrun is the side plchmi trusts.
#pragma once

#include <cstdint>
#include <type_traits>

#include "plc/debug/condition_code.hpp"
#include "plc/types.hpp"

namespace plc::hmi::ipc {

// Append only: the values are the record format.
enum class Verb : std::uint8_t {
  None,
  Read,
  Write,
  Force,
  Unforce,     // target
  UnforceAll,  // every force on a variable the HMI may force
  Pause,
  Step,  // count scans
  Continue,
  Break,      // the code; count = hits
  Delete,     // count = breakpoint id
  DeleteAll,  // every breakpoint
};
inline constexpr std::uint8_t kVerbs = std::uint8_t(Verb::DeleteAll) + 1;

// Why plcrun refused a record (ReplyRecord::reason). Append only.
enum class Reason : std::uint8_t {
  Ok,
  Malformed,     // a field out of range: the verb, a count, a length, an enum
  Stale,         // made for another cell layout (the cell was rebuilt since)
  BadOperand,    // an index beyond the layout, an address outside the image
  NotWritable,   // the layout says the HMI may not write it
  NotForceable,  // ... may not force it
  NoStops,       // pause/step/continue/break/delete with stop_commands off
  Busy,          // the debugger console held the session too long
  NoDebugger,    // this cell serves no commands
  Refused,       // the debugger said no (text says why)
  BadCode,       // the condition's code does not validate or bind (text)
};
inline constexpr std::uint8_t kReasons = std::uint8_t(Reason::BadCode) + 1;
const char* to_string(Reason r);

struct WireOperand {
  enum Kind : std::uint8_t { None = 0, Var = 1, Address = 2 };
  std::uint8_t kind = None;
  std::uint8_t area = 0, size = 0, bit = 0;  // Address: io::Area, io::AddrSize, bit
  std::uint32_t value = 0;                   // Var: layout index; Address: byte offset
};

struct WireInstr {
  std::uint8_t op = 0;  // debug::ConditionCode::Op
  std::uint8_t pad = 0;
  std::uint16_t index = 0;
};

struct WireConst {
  std::uint8_t real = 0;
  std::uint8_t pad[7] = {};
  std::uint64_t bits = 0;  // the LINT, or the LREAL's bits
};

inline constexpr std::size_t kMaxReadOperands = 32;
inline constexpr std::size_t kMaxCodeOperands = debug::ConditionCode::kMaxOperands;
inline constexpr std::size_t kMaxStep = 1'000'000;

struct CommandRecord {
  std::uint32_t token = 0;       // plchmi's own number, echoed in the reply
  std::uint8_t verb = 0;         // Verb
  std::uint8_t restore = 0;      // Unforce, UnforceAll: write back the value from before the force
  std::uint16_t n_operands = 0;  // Read: operands; Break: the code's operands
  std::uint64_t generation = 0;  // the layout the indices refer to
  std::uint64_t count = 0;       // Step: scans; Break: hits; Delete: id
  WireOperand target;            // Write, Force, Unforce
  alignas(8) std::uint8_t value[8] = {};  // Write, Force: native storage of the type
  std::uint16_t n_instrs = 0, n_consts = 0;
  std::uint32_t pad = 0;
  WireOperand operands[kMaxCodeOperands];
  WireInstr instrs[debug::ConditionCode::kMaxInstrs];
  WireConst consts[debug::ConditionCode::kMaxConsts];
};
static_assert(std::is_trivially_copyable_v<CommandRecord>);
static_assert(kMaxReadOperands <= kMaxCodeOperands);

struct WireValue {
  std::uint8_t has_value = 0;  // 0: error holds why there is no value
  std::uint8_t type = 0;       // VarType
  std::uint8_t forced = 0;
  std::uint8_t image_differs = 0;
  std::uint8_t pad[4] = {};
  alignas(8) std::uint8_t bytes[96] = {};  // native storage (a STRING is a plc::STRING)
  alignas(8) std::uint8_t image[8] = {};   // the global image's value, when it differs
  char error[120] = {};                    // NUL-terminated
};
static_assert(sizeof(STRING) <= sizeof(WireValue::bytes));

inline constexpr std::size_t kReplyText = 1024;

struct ReplyRecord {
  std::uint32_t token = 0;
  std::uint8_t reason = 0;  // Reason
  std::uint8_t n_values = 0;
  std::uint16_t text_size = 0;
  char text[kReplyText] = {};  // the debugger's answer, or why it refused
  WireValue values[kMaxReadOperands];
};
static_assert(std::is_trivially_copyable_v<ReplyRecord>);

}  // namespace plc::hmi::ipc

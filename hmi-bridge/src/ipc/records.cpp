#include "plc/hmi/ipc/records.hpp"

namespace plc::hmi::ipc {

const char* to_string(Reason r) {
  switch (r) {
    case Reason::Ok:
      return "ok";
    case Reason::Malformed:
      return "malformed record";
    case Reason::Stale:
      return "stale: the cell was rebuilt";
    case Reason::BadOperand:
      return "no such variable or address";
    case Reason::NotWritable:
      return "not writable from the HMI";
    case Reason::NotForceable:
      return "not forceable from the HMI";
    case Reason::NoStops:
      return "stop_commands is false";
    case Reason::Busy:
      return "busy";
    case Reason::NoDebugger:
      return "this cell serves no commands";
    case Reason::Refused:
      return "refused";
    case Reason::BadCode:
      return "condition code refused";
  }
  return "unknown reason";
}

}  // namespace plc::hmi::ipc

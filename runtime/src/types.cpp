#include "plc/types.hpp"

namespace plc {

const char* to_string(VarType t) {
  switch (t) {
    case VarType::BOOL:
      return "BOOL";
    case VarType::SINT:
      return "SINT";
    case VarType::INT:
      return "INT";
    case VarType::DINT:
      return "DINT";
    case VarType::LINT:
      return "LINT";
    case VarType::USINT:
      return "USINT";
    case VarType::UINT:
      return "UINT";
    case VarType::UDINT:
      return "UDINT";
    case VarType::ULINT:
      return "ULINT";
    case VarType::BYTE:
      return "BYTE";
    case VarType::WORD:
      return "WORD";
    case VarType::DWORD:
      return "DWORD";
    case VarType::LWORD:
      return "LWORD";
    case VarType::REAL:
      return "REAL";
    case VarType::LREAL:
      return "LREAL";
    case VarType::TIME:
      return "TIME";
    case VarType::STRING:
      return "STRING";
  }
  return "?";
}

std::size_t size_of(VarType t) {
  switch (t) {
    case VarType::BOOL:
    case VarType::SINT:
    case VarType::USINT:
    case VarType::BYTE:
      return 1;
    case VarType::INT:
    case VarType::UINT:
    case VarType::WORD:
      return 2;
    case VarType::DINT:
    case VarType::UDINT:
    case VarType::DWORD:
    case VarType::REAL:
      return 4;
    case VarType::LINT:
    case VarType::ULINT:
    case VarType::LWORD:
    case VarType::LREAL:
    case VarType::TIME:
      return 8;
    case VarType::STRING:
      return sizeof(STRING);
  }
  return 0;
}

}  // namespace plc

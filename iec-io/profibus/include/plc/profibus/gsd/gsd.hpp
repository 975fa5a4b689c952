// ASCII GSD files (PROFIBUS "Gerätestammdaten", the format of the seed's
// GWT_5610.gsd): `#Profibus_DP`, then `Keyword = Value` lines. Keywords are
// case-insensitive; `;` starts a comment (outside a string); a line ending
// in `\` continues on the next; values are numbers (decimal or 0x hex),
// "strings", or lists separated by commas. Blocks:
//   Module = "name" CFG,CFG...  [module reference on its own line]
//     Ext_Module_Prm_Data_Len = n
//     Ext_User_Prm_Data_Const(offset) = bytes ...
//     Ext_User_Prm_Data_Ref(offset) = reference
//   EndModule
//   ExtUserPrmData = reference "name"
//     Unsigned8|Unsigned16|Unsigned32|Signed8..32|Bit(b)|BitArea(b1-b2) default min-max | a,b,c
//     Prm_Text_Ref = n
//   EndExtUserPrmData
//   PrmText = n  Text(value) = "text" ... EndPrmText
// Every other keyword is kept as text by name (the last one wins).
// Errors name the file and the line: `FILE:LINE: message`.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace plc::profibus::gsd {

struct GsdError : std::runtime_error {
  GsdError(const std::string& file_, std::size_t line_, const std::string& msg)
      : std::runtime_error(file_ + ":" + std::to_string(line_) + ": " + msg),
        file(file_),
        line(line_) {}
  std::string file;
  std::size_t line;
};

// The default value of a parameter at an offset of the parameter data.
struct PrmRef {
  std::size_t offset = 0;
  std::uint32_t reference = 0;
};
struct PrmConst {
  std::size_t offset = 0;
  std::vector<std::uint8_t> bytes;
};

struct Module {
  std::string name;
  std::vector<std::uint8_t> cfg;
  std::optional<std::uint32_t> reference;
  std::size_t prm_len = 0;  // Ext_Module_Prm_Data_Len
  std::vector<PrmConst> consts;
  std::vector<PrmRef> refs;
  std::size_t line = 0;
  std::size_t input_bytes = 0, output_bytes = 0;  // from the Cfg bytes
};

struct ExtUserPrm {
  std::uint32_t reference = 0;
  std::string name;
  std::string type;    // Unsigned8, Bit, BitArea, ...
  int bit_first = -1;  // Bit(b), BitArea(b1-b2)
  int bit_last = -1;
  std::int64_t def = 0, min = 0, max = 0;
  std::vector<std::int64_t> allowed;  // "a,b,c" instead of min-max
  std::optional<std::uint32_t> text_ref;
  std::size_t line = 0;
};

struct PrmText {
  std::uint32_t reference = 0;
  std::map<std::int64_t, std::string> texts;
};

struct Value {
  std::string text;  // as written (strings without their quotes)
  std::size_t line = 0;
};

class Gsd {
 public:
  std::string file;
  std::map<std::string, Value> keys;  // lower-case keyword -> value
  std::vector<Module> modules;
  std::map<std::uint32_t, ExtUserPrm> ext_user_prm;
  std::map<std::uint32_t, PrmText> prm_texts;
  std::vector<PrmConst> consts;  // global Ext_User_Prm_Data_Const
  std::vector<PrmRef> refs;      // global Ext_User_Prm_Data_Ref

  [[nodiscard]] const Value* find(std::string_view key) const;
  [[nodiscard]] std::string text(std::string_view key, const std::string& def = "") const;
  // A numeric keyword; `def` when absent; GsdError at its line when not a number.
  [[nodiscard]] std::int64_t number(std::string_view key, std::int64_t def) const;

  [[nodiscard]] std::uint16_t ident() const {
    return static_cast<std::uint16_t>(number("Ident_Number", 0));
  }
  [[nodiscard]] bool modular() const { return number("Modular_Station", 0) != 0; }
  [[nodiscard]] std::size_t max_modules() const;
  [[nodiscard]] bool freeze_supported() const { return number("Freeze_Mode_supp", 0) != 0; }
  [[nodiscard]] bool sync_supported() const { return number("Sync_Mode_supp", 0) != 0; }
  // <suffix>_supp = 1 (suffix as in fdl::BaudProfile::gsd_suffix).
  [[nodiscard]] bool baud_supported(const char* suffix) const;
  // MaxTsdr_<suffix>, when given.
  [[nodiscard]] std::optional<std::uint32_t> max_tsdr(const char* suffix) const;
  // Min_Slave_Intervall in units of 100 us.
  [[nodiscard]] std::uint32_t min_slave_interval() const;
  [[nodiscard]] std::size_t max_diag_len() const {
    return static_cast<std::size_t>(number("Max_Diag_Data_Len", 6));
  }

  // The module by name (exact, else case-insensitive), or nullptr.
  [[nodiscard]] const Module* module(std::string_view name) const;

  // The user parameter data (after the 7 standard Set_Prm bytes) for the
  // chosen modules: User_Prm_Data (or User_Prm_Data_Len zeros) with the
  // global Ext_User_Prm_Data_Const/Ref applied, then each module's block.
  [[nodiscard]] std::vector<std::uint8_t> user_prm_data(
      const std::vector<const Module*>& chosen) const;
};

// Parses GSD text; `file` names it in errors. Throws GsdError.
Gsd parse_gsd(std::string_view text, const std::string& file);
// Reads and parses a file; GsdError (line 0) when it cannot be read.
Gsd load_gsd(const std::string& path);

}  // namespace plc::profibus::gsd

// Fuzz target: cell config text -> CellConfig -> Runtime (docs/config.md).
// Any text must end in a built runtime or a ConfigError naming
// file:line:column; never a crash, a hang, a huge allocation or another
// exception type (plcrun turns only ConfigError into exit code 2).
#include <cstdint>
#include <string>

#include "plc/cell_config.hpp"
#include "plc/runtime.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const plc::CellConfig cfg = plc::parse_cell_config(text, "fuzz.yaml");
    plc::Runtime rt(cfg);
  } catch (const plc::ConfigError&) {
  }
  return 0;
}

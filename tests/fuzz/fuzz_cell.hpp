// The cell the runtime-side targets (condition, debugger, recording) run:
// programs/filling_cell, three device models with acyclic traffic and every
// FB family, so the registry has every kind of variable.
#pragma once

#include <cstdlib>
#include <string>

#include "plc/cell_config.hpp"

namespace plc::fuzz {

inline const CellConfig& filling_cell() {
  static const CellConfig cfg = [] {
    const char* src = std::getenv("PLC_SOURCE_DIR");
    return load_cell_config(std::string(src ? src : PLC_DEFAULT_SOURCE_DIR) +
                            "/programs/filling_cell/cell.yaml");
  }();
  return cfg;
}

}  // namespace plc::fuzz

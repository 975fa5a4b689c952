// plcrun --new-cell DIR: writes a cell project from the template installed
// in share/softplc/cell-template (the build folder has the same layout).
#pragma once

#include <string>

namespace plc {
// Returns "" on success, else why not (nothing written).
std::string write_new_cell(const std::string& dir);
}  // namespace plc

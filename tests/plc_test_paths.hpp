// Where the tests find the repository (example configs) and this build's
// executables (plcrun). Both are compiled in by plc_add_gtest
// (CMakeLists.txt), so a test runs against the build it belongs to in any
// build folder, and never against a stale binary from another one.
#pragma once

#include <string>

#if !defined(PLC_SOURCE_DIR) || !defined(PLC_BIN_DIR)
#error "PLC_SOURCE_DIR and PLC_BIN_DIR must be defined: build tests with plc_add_gtest"
#endif

namespace plctest {

inline std::string source_dir() { return PLC_SOURCE_DIR; }
inline std::string bin_dir() { return PLC_BIN_DIR; }
// A file of the repository, e.g. source_path("programs/demo/cell.yaml").
inline std::string source_path(const std::string& relative) {
  return source_dir() + "/" + relative;
}

}  // namespace plctest

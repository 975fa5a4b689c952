// A cell running the Filler program from a cell library that the test
// copies into a folder of its own (so a "new build" can replace the file
// at the same path, as a user's `cmake --build` does).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>

#include "plc/cell_config.hpp"
#include "plc/runtime.hpp"

namespace plc::test {

namespace fs = std::filesystem;

inline std::string cell_yaml() {
  return R"(
cell: online
libraries: [libfiller.so]
tasks:
  - name: fast
    period: 10ms
    programs: [Main]
  - name: slow
    period: 50ms
    programs: [Other]
programs:
  - name: Main
    type: Filler
  - name: Other
    type: Filler
)";
}

class CellFolder {
 public:
  CellFolder() {
    dir_ = fs::temp_directory_path() /
           ("softplc-online-" + std::to_string(getpid()) + "-" + std::to_string(next()++));
    fs::create_directories(dir_);
  }
  ~CellFolder() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  // "Builds" the library: puts `built` at the path the config names.
  void install(const std::string& built) {
    fs::copy_file(built, library(), fs::copy_options::overwrite_existing);
  }
  [[nodiscard]] std::string library() const { return (dir_ / "libfiller.so").string(); }
  [[nodiscard]] std::string config_file() const { return (dir_ / "cell.yaml").string(); }
  [[nodiscard]] CellConfig config() const { return parse_cell_config(cell_yaml(), config_file()); }

 private:
  static int& next() {
    static int n = 0;
    return n;
  }
  fs::path dir_;
};

inline std::string value(const Runtime& rt, const std::string& path) {
  const VarInfo* v = rt.vars().find(path);
  return v ? VarRegistry::format(*v) : "<none: " + path + ">";
}

}  // namespace plc::test

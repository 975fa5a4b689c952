// Cell libraries: shared objects with programs (and device models, plugins)
// built outside this tree against the installed runtime
// (softplc_add_cell_library), named in a cell config under `libraries:`.
//
// Loading one: the file is copied to a private temporary file and that copy
// is dlopen'ed (RTLD_NOW | RTLD_LOCAL). The copy is what makes online change
// possible: glibc hands back the already loaded object for a path it has
// seen, so a new build at the same path would never load; and the linker
// rewriting the file under a mapped library would corrupt the running code.
// Its static registrations (PLC_REGISTER_PROGRAM, ...) run inside dlopen and
// are captured, not applied (ProgramRegistry::set_capture); they reach the
// registries only after the library's ABI version (plc/abi.hpp) matched. A
// library that fails (missing file, dlopen error, missing ABI symbol, other
// ABI) is unloaded again and changes nothing.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "plc/io/device_model.hpp"
#include "plc/io/plugin.hpp"
#include "plc/program.hpp"

namespace plc {

class CellLibraryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CellLibrary {
 public:
  // Loads the library at `path` (captured registrations, checked ABI).
  // Throws CellLibraryError saying what failed. `file`, when given, is
  // where the bytes come from (a replay's kept copy of an older build,
  // plc/debug/recording.hpp); the library is still the one named `path`.
  static std::shared_ptr<CellLibrary> open(const std::string& path, const std::string& file = "");
  ~CellLibrary();
  CellLibrary(const CellLibrary&) = delete;
  CellLibrary& operator=(const CellLibrary&) = delete;

  [[nodiscard]] const std::string& path() const { return path_; }
  // Which build this is: CRC-32 (IEEE 802.3) and size of the loaded bytes.
  // A recording notes it; a replay loads the same build again.
  [[nodiscard]] std::uint32_t crc32() const { return crc32_; }
  [[nodiscard]] std::uint64_t size() const { return size_; }
  // What the library registered (its own factories).
  [[nodiscard]] const std::map<std::string, ProgramFactory>& programs() const { return programs_; }
  [[nodiscard]] const std::map<std::string, io::DeviceModelFactory>& models() const {
    return models_;
  }
  [[nodiscard]] const std::map<std::string, io::PluginFactory>& plugins() const { return plugins_; }
  // Puts its factories into the process's registries (replacing those of
  // an older build of the same library).
  void commit() const;

 private:
  CellLibrary() = default;
  std::string path_;
  std::uint32_t crc32_ = 0;
  std::uint64_t size_ = 0;
  void* handle_ = nullptr;
  std::map<std::string, ProgramFactory> programs_;
  std::map<std::string, io::DeviceModelFactory> models_;
  std::map<std::string, io::PluginFactory> plugins_;
};

// CRC-32 (IEEE 802.3) and size of a file's bytes; nullopt if it cannot be
// read.
struct FileCrc {
  std::uint32_t crc32 = 0;
  std::uint64_t size = 0;
  friend bool operator==(const FileCrc&, const FileCrc&) = default;
};
std::optional<FileCrc> file_crc32(const std::string& file);

// The process's current build of each library, by absolute path: loaded
// (and committed) at the first use, shared by every Runtime of the process
// (a debugger restart reuses it). Never unloaded while current.
std::shared_ptr<CellLibrary> use_cell_library(const std::string& path);
// Online change: `lib` becomes the current build of its path and its
// factories replace the older build's in the registries.
void make_current(const std::shared_ptr<CellLibrary>& lib);

}  // namespace plc

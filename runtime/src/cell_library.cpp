#include "plc/cell_library.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <boost/crc.hpp>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "plc/abi.hpp"

namespace plc {
namespace {

namespace fs = std::filesystem;

// Collects what the three registries get while `fn` runs.
struct Capture {
  std::map<std::string, ProgramFactory> programs;
  std::map<std::string, io::DeviceModelFactory> models;
  std::map<std::string, io::PluginFactory> plugins;
  template <class F>
  void during(F&& fn) {
    ProgramRegistry::instance().set_capture(&programs);
    io::DeviceModelRegistry::instance().set_capture(&models);
    io::PluginRegistry::instance().set_capture(&plugins);
    fn();
    ProgramRegistry::instance().set_capture(nullptr);
    io::DeviceModelRegistry::instance().set_capture(nullptr);
    io::PluginRegistry::instance().set_capture(nullptr);
  }
};

// A private copy of the file to dlopen (see the header), removed once it is
// mapped.
std::string private_copy(const std::string& path) {
  std::error_code ec;
  const fs::path tmp = fs::temp_directory_path(ec);  // TMPDIR may name no folder
  if (ec) throw CellLibraryError("no folder for a temporary copy: " + ec.message());
  std::string tmpl = (tmp / "softplc-cell-XXXXXX.so").string();
  const int fd = mkstemps(tmpl.data(), 3);
  if (fd < 0)
    throw CellLibraryError("cannot make a temporary copy: " + std::string(strerror(errno)));
  close(fd);
  fs::copy_file(path, tmpl, fs::copy_options::overwrite_existing, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmpl, ignored);
    throw CellLibraryError("cannot copy it to " + tmpl + ": " + ec.message());
  }
  return tmpl;
}

std::mutex& libraries_mutex() {
  static std::mutex m;
  return m;
}
// Leaked on purpose: destroying it at exit would unload libraries whose
// factories the registries still hold.
std::map<std::string, std::shared_ptr<CellLibrary>>& current_libraries() {
  static auto* m = new std::map<std::string, std::shared_ptr<CellLibrary>>;
  return *m;
}

}  // namespace

std::optional<FileCrc> file_crc32(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  boost::crc_32_type crc;
  FileCrc r;
  char buf[64 << 10];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    crc.process_bytes(buf, static_cast<std::size_t>(in.gcount()));
    r.size += static_cast<std::uint64_t>(in.gcount());
  }
  if (in.bad()) return std::nullopt;
  r.crc32 = crc.checksum();
  return r;
}

std::shared_ptr<CellLibrary> CellLibrary::open(const std::string& path, const std::string& file) {
  const std::string& from = file.empty() ? path : file;
  std::error_code ec;
  if (!fs::is_regular_file(from, ec))
    throw CellLibraryError("no such file (build the cell library first, e.g. cmake --build build)");
  const std::string copy = private_copy(from);
  std::shared_ptr<CellLibrary> lib(new CellLibrary);
  lib->path_ = path;
  // The build's identity: of the copy, the bytes that are really loaded.
  if (auto c = file_crc32(copy)) {
    lib->crc32_ = c->crc32;
    lib->size_ = c->size;
  }
  Capture cap;
  cap.during([&] { lib->handle_ = dlopen(copy.c_str(), RTLD_NOW | RTLD_LOCAL); });
  fs::remove(copy, ec);
  if (!lib->handle_) {
    const char* why = dlerror();
    std::string msg = why ? why : "dlopen failed";
    // dlerror names the temporary copy; name the user's file instead.
    for (auto p = msg.find(copy); p != std::string::npos; p = msg.find(copy))
      msg.replace(p, copy.size(), from);
    throw CellLibraryError("cannot load: " + msg);
  }
  const auto* abi = static_cast<const unsigned*>(dlsym(lib->handle_, PLC_CELL_ABI_SYMBOL));
  if (!abi)
    throw CellLibraryError(
        "not a cell library: it has no symbol " PLC_CELL_ABI_SYMBOL
        " (build it with softplc_add_cell_library() from find_package(softplc))");
  if (*abi != PLC_ABI_VERSION)
    throw CellLibraryError("built against softplc ABI version " + std::to_string(*abi) +
                           ", this runtime (softplc " PLC_VERSION ") has ABI version " +
                           std::to_string(PLC_ABI_VERSION) + ": rebuild it against this runtime");
  lib->programs_ = std::move(cap.programs);
  lib->models_ = std::move(cap.models);
  lib->plugins_ = std::move(cap.plugins);
  return lib;
}

CellLibrary::~CellLibrary() {
  // The factories' code is in the library: drop them before unloading it.
  programs_.clear();
  models_.clear();
  plugins_.clear();
  if (handle_) dlclose(handle_);
}

void CellLibrary::commit() const {
  for (const auto& [n, f] : programs_) ProgramRegistry::instance().add(n, f);
  for (const auto& [n, f] : models_) io::DeviceModelRegistry::instance().add(n, f);
  for (const auto& [n, f] : plugins_) io::PluginRegistry::instance().add(n, f);
}

std::shared_ptr<CellLibrary> use_cell_library(const std::string& path) {
  std::lock_guard<std::mutex> lock(libraries_mutex());
  auto& libs = current_libraries();
  if (auto it = libs.find(path); it != libs.end()) return it->second;
  auto lib = CellLibrary::open(path);
  lib->commit();
  libs[path] = lib;
  return lib;
}

void make_current(const std::shared_ptr<CellLibrary>& lib) {
  std::lock_guard<std::mutex> lock(libraries_mutex());
  lib->commit();
  current_libraries()[lib->path()] = lib;
}

}  // namespace plc

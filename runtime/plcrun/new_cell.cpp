#include "new_cell.hpp"

#include <filesystem>
#include <system_error>

namespace plc {
namespace fs = std::filesystem;

std::string write_new_cell(const std::string& dir) {
  if (dir.empty()) return "DIR is an empty path (give a new folder)";
  std::error_code ec;
  // bin/plcrun -> share/softplc/cell-template, installed or in a build folder.
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "cannot find plcrun's own location: " + ec.message();
  const fs::path tmpl = exe.parent_path().parent_path() / "share" / "softplc" / "cell-template";
  if (!fs::is_directory(tmpl, ec)) return "the cell template is missing: " + tmpl.string();
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec))
    return dir + " exists and is not empty (give a new folder)";
  fs::create_directories(dir, ec);
  if (ec) return "cannot create " + dir + ": " + ec.message();
  fs::copy(tmpl, dir, fs::copy_options::recursive, ec);
  if (ec) return "cannot copy the template to " + dir + ": " + ec.message();
  return {};
}

}  // namespace plc

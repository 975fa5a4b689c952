#include "plc/config_path.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace plc {

namespace fs = std::filesystem;

std::string config_folder(const std::string& config_file) {
  const fs::path parent = fs::path(config_file).parent_path();
  return parent.empty() ? "." : parent.string();
}

std::string path_in_folder(const std::string& folder, const std::string& path) {
  if (path.empty() || fs::path(path).is_absolute()) return path;
  fs::path out;
  for (const fs::path& part : fs::path(folder) / path)
    if (part != ".") out /= part;
  return out.empty() ? "." : out.string();
}

std::string config_relative_path(const std::string& config_file, const std::string& path) {
  return path_in_folder(config_folder(config_file), path);
}

std::optional<std::string> absolute_path(const std::string& path, std::string& error) {
  if (path.empty()) {
    error = "an empty path";
    return std::nullopt;
  }
  std::error_code ec;
  const fs::path a = fs::absolute(path, ec);
  if (ec) {
    error = "cannot make '" + path + "' absolute: " + ec.message();
    return std::nullopt;
  }
  return a.lexically_normal().string();
}

std::string writable_file_problem(const std::string& path) {
  if (path.empty()) return "an empty path names no file";
  const std::string dir = config_folder(path);
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0)
    return errno == ENOENT ? "the folder '" + dir + "' does not exist"
                           : "cannot look at the folder '" + dir + "': " + std::strerror(errno);
  if (!S_ISDIR(st.st_mode)) return "'" + dir + "' is not a folder";
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    return "the folder '" + dir + "' is not writable (" + std::strerror(errno) + ")";
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return "is a folder, not a file";
    if (::access(path.c_str(), W_OK) != 0)
      return std::string("cannot write: ") + std::strerror(errno);
  }
  return {};
}

std::string readable_file_problem(const std::string& path) {
  if (path.empty()) return "an empty path names no file";
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::string("cannot open: ") + std::strerror(errno);
  if (S_ISDIR(st.st_mode)) return "is a folder, not a file";
  if (!S_ISREG(st.st_mode))
    return std::string("is not a regular file (") +
           (S_ISFIFO(st.st_mode)   ? "a FIFO"
            : S_ISSOCK(st.st_mode) ? "a socket"
                                   : "a device") +
           "): give the file itself";
  if (::access(path.c_str(), R_OK) != 0) return std::string("cannot read: ") + std::strerror(errno);
  return {};
}

}  // namespace plc

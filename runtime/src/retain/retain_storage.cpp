#include "plc/retain/retain_storage.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

namespace plc::retain {
namespace {

std::string sys_error(const std::string& what, const std::string& file) {
  return what + " '" + file + "': " + std::strerror(errno);
}

}  // namespace

Storage::Storage(std::string path) : path_(std::move(path)), write_fn_(&::write) {
  const auto slash = path_.rfind('/');
  dir_ = slash == std::string::npos ? "." : slash == 0 ? "/" : path_.substr(0, slash);
}

std::string Storage::copy_path(std::uint64_t sequence) const {
  return path_ + (sequence % 2 ? ".a" : ".b");
}

std::string Storage::write(std::span<const std::uint8_t> bytes, std::uint64_t sequence) {
  const std::string tmp = path_ + ".tmp";
  const std::string dst = copy_path(sequence);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return sys_error("cannot create", tmp);
  std::string err;
  for (std::size_t done = 0; done < bytes.size() && err.empty();) {
    const ssize_t w = write_fn_(fd, bytes.data() + done, bytes.size() - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      if (w == 0) errno = ENOSPC;
      err = sys_error("cannot write", tmp);
    } else {
      done += std::size_t(w);
    }
  }
  // The data must be on the disk before the rename makes it the copy.
  if (err.empty() && ::fsync(fd) != 0) err = sys_error("cannot fsync", tmp);
  if (::close(fd) != 0 && err.empty()) err = sys_error("cannot close", tmp);
  if (err.empty() && std::rename(tmp.c_str(), dst.c_str()) != 0)
    err = sys_error("cannot rename onto", dst);
  if (!err.empty()) {
    ::unlink(tmp.c_str());
    return err;
  }
  // The rename itself is only durable once the folder is (Beremiz skips this).
  const int dfd = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd < 0) return sys_error("cannot open the folder", dir_);
  if (::fsync(dfd) != 0) err = sys_error("cannot fsync the folder", dir_);
  ::close(dfd);
  return err;
}

Storage::Loaded Storage::load() const {
  Loaded out;
  for (std::uint64_t s : {1, 2}) {
    const std::string file = copy_path(s);
    struct stat st {};
    if (::stat(file.c_str(), &st) != 0) continue;  // never written: not a problem
    if (std::size_t(st.st_size) > kMaxFileBytes) {
      out.problems.push_back(file + ": " + std::to_string(st.st_size) + " bytes, too large");
      continue;
    }
    std::ifstream in(file, std::ios::binary);
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                    std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) {
      out.problems.push_back(file + ": cannot read");
      continue;
    }
    std::string why;
    auto img = decode(bytes, why);
    if (!img) {
      out.problems.push_back(file + ": " + why);
      continue;
    }
    if (!out.image || img->sequence > out.image->sequence) {
      out.image = std::move(img);
      out.from = file;
    }
  }
  return out;
}

std::string Storage::discard() const {
  for (const std::string& f : {copy_path(1), copy_path(2), path_ + ".tmp"})
    if (::unlink(f.c_str()) != 0 && errno != ENOENT) return sys_error("cannot remove", f);
  return {};
}

std::string Storage::check_folder() const {
  struct stat st {};
  if (::stat(dir_.c_str(), &st) != 0)
    return errno == ENOENT ? "the folder '" + dir_ + "' does not exist"
                           : sys_error("cannot look at the folder", dir_);
  if (!S_ISDIR(st.st_mode)) return "'" + dir_ + "' is not a folder";
  // W for the temporary copy and the renames, X to reach the files.
  if (::access(dir_.c_str(), W_OK | X_OK) != 0)
    return "the folder '" + dir_ + "' is not writable (" + std::strerror(errno) + ")";
  return {};
}

void check_file(const CellConfig& cfg) {
  const std::string why = Storage(cfg.retain.path).check_folder();
  if (!why.empty())
    throw ConfigError(
        cfg.file, cfg.retain.file.mark,
        "key 'file': " + why + " (the retain file '" + cfg.retain.path + "' could never be saved)");
}

}  // namespace plc::retain

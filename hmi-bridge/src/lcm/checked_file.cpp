#include "plc/hmi/checked_file.hpp"

#include <fcntl.h>
#include <string.h>  // explicit_bzero
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>

namespace plc::hmi {

namespace {

struct OwnedFd {
  int fd;
  explicit OwnedFd(int f) : fd(f) {}
  OwnedFd(const OwnedFd&) = delete;
  OwnedFd& operator=(const OwnedFd&) = delete;
  ~OwnedFd() {
    if (fd >= 0) ::close(fd);
  }
};

std::string octal_mode(mode_t m) {
  char b[8];
  std::snprintf(b, sizeof b, "%04o", unsigned(m & 07777));
  return b;
}

}  // namespace

std::optional<std::string> read_checked_file(const std::string& path, const FileRules& rules,
                                             std::string& err) {
  const std::string subject = rules.what + " '" + path + "'";
  OwnedFd f(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK));
  struct stat st {};
  if (f.fd < 0 || ::fstat(f.fd, &st) != 0) {
    err = "cannot read " + subject;
    return std::nullopt;
  }
  if (!S_ISREG(st.st_mode)) {
    err = subject + " is not a regular file";
    return std::nullopt;
  }
  if (rules.secret && (st.st_mode & 077) != 0) {
    err = subject + " is readable or writable by group or others (mode " + octal_mode(st.st_mode) +
          "): " + rules.exposure + "; chmod 600 " + path;
    return std::nullopt;
  }
  if (rules.secret && st.st_uid != ::geteuid() && st.st_uid != 0) {
    err = subject + " belongs to uid " + std::to_string(st.st_uid) + ", neither this user (uid " +
          std::to_string(::geteuid()) + ") nor root: its owner can change its mode";
    return std::nullopt;
  }
  if (std::size_t(st.st_size) > rules.max_bytes) {
    err = subject + " is " + std::to_string(st.st_size) + " bytes" + rules.too_large;
    return std::nullopt;
  }
  // One byte more than allowed is asked for, to see a file that grew since
  // fstat.
  std::string text(rules.max_bytes + 1, '\0');
  std::size_t got = 0;
  for (int i = 0; i < 64 && got < text.size(); ++i) {  // bounded: short reads of a small file
    const ssize_t n = ::read(f.fd, text.data() + got, text.size() - got);
    if (n <= 0) break;
    got += std::size_t(n);
  }
  if (got > rules.max_bytes) {
    explicit_bzero(text.data(), text.size());
    err = subject + " is more than " + std::to_string(rules.max_bytes) + " bytes";
    return std::nullopt;
  }
  text.resize(got);
  return text;
}

}  // namespace plc::hmi

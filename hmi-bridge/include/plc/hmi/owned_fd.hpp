// Small pieces of the checks of a file that holds a secret (the HMI key,
// command_auth.cpp; the web HMI's TLS key, tls_files.cpp): a descriptor
// closed on every return, and a mode written as chmod takes it.
#pragma once

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <string>

namespace plc::hmi {

struct OwnedFd {
  int fd;
  explicit OwnedFd(int f) : fd(f) {}
  OwnedFd(const OwnedFd&) = delete;
  OwnedFd& operator=(const OwnedFd&) = delete;
  ~OwnedFd() {
    if (fd >= 0) ::close(fd);
  }
};

// "0644" for a mode with those permission bits.
inline std::string octal_mode(mode_t m) {
  char b[8];
  std::snprintf(b, sizeof b, "%04o", unsigned(m & 07777));
  return b;
}

}  // namespace plc::hmi

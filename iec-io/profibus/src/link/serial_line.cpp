#include "plc/profibus/link/serial_line.hpp"

#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>

namespace plc::profibus::link {

namespace {
std::string errno_text(const std::string& what) { return what + ": " + std::strerror(errno); }

bool path_is_pty(const std::string& path) {
  char real[PATH_MAX];
  if (!realpath(path.c_str(), real)) return false;
  return std::strncmp(real, "/dev/pts/", 9) == 0;
}

// TCFLSH without <termios.h> (see termios2.cpp): 0 = TCIFLUSH.
void flush_in(int fd) { (void)ioctl(fd, TCFLSH, 0); }
}  // namespace

std::unique_ptr<SerialLine> SerialLine::open_tty(const std::string& path, std::uint32_t baud) {
  std::unique_ptr<SerialLine> l(new SerialLine);
  l->fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (l->fd_ < 0) throw LineError(errno_text("serial:" + path));
  l->pty_ = path_is_pty(path);
  if (!set_line_mode(l->fd_, baud) && !l->pty_)
    throw LineError(errno_text("serial:" + path + ": 8E1 at " + std::to_string(baud) + " bit/s"));
  flush_in(l->fd_);
  l->what_ = "serial " + path + (l->pty_ ? " (a pty)" : "");
  return l;
}

std::unique_ptr<SerialLine> SerialLine::make_pty(const std::string& link_path, std::uint32_t baud) {
  std::unique_ptr<SerialLine> l(new SerialLine);
  l->pty_ = true;
  l->fd_ = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (l->fd_ < 0 || grantpt(l->fd_) != 0 || unlockpt(l->fd_) != 0)
    throw LineError(errno_text("pty:" + link_path + ": posix_openpt"));
  const char* name = ptsname(l->fd_);
  if (!name) throw LineError(errno_text("pty:" + link_path + ": ptsname"));
  const std::string slave = name;
  l->hold_ = ::open(slave.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (l->hold_ < 0) throw LineError(errno_text("pty:" + link_path + ": " + slave));
  // Raw mode on the slave side (the line discipline is there): no echo, no
  // CR/LF mapping, every byte through.
  if (!set_line_mode(l->hold_, baud))
    throw LineError(errno_text("pty:" + link_path + ": raw mode"));
  struct stat st {};
  if (lstat(link_path.c_str(), &st) == 0) {
    if (!S_ISLNK(st.st_mode))
      throw LineError("pty:" + link_path + ": exists and is not a symlink (not replaced)");
    ::unlink(link_path.c_str());
  }
  if (::symlink(slave.c_str(), link_path.c_str()) != 0)
    throw LineError(errno_text("pty:" + link_path + ": symlink to " + slave));
  l->link_ = link_path;
  l->what_ = "pty " + link_path + " -> " + slave;
  return l;
}

SerialLine::~SerialLine() {
  if (fd_ >= 0) ::close(fd_);
  if (hold_ >= 0) ::close(hold_);
  if (!link_.empty()) ::unlink(link_.c_str());
}

bool SerialLine::send(std::span<const std::uint8_t> telegram) {
  const ssize_t n = ::write(fd_, telegram.data(), telegram.size());
  if (n != static_cast<ssize_t>(telegram.size())) {
    ++counters_.tx_dropped;
    return false;
  }
  ++counters_.tx_telegrams;
  counters_.tx_bytes += telegram.size();
  return true;
}

std::size_t SerialLine::receive(std::span<std::uint8_t> buf) {
  const ssize_t n = ::read(fd_, buf.data(), buf.size());
  if (n <= 0) return 0;
  counters_.rx_bytes += static_cast<std::uint64_t>(n);
  return static_cast<std::size_t>(n);
}

void SerialLine::flush_input() {
  std::uint8_t b[512];
  for (int i = 0; i < 64 && ::read(fd_, b, sizeof b) > 0; ++i) {
  }
  if (!pty_) flush_in(fd_);
}

std::unique_ptr<Line> open_line(const std::string& spec, std::uint32_t baud) {
  if (spec.rfind("serial:", 0) == 0 && spec.size() > 7)
    return SerialLine::open_tty(spec.substr(7), baud);
  if (spec.rfind("pty:", 0) == 0 && spec.size() > 4)
    return SerialLine::make_pty(spec.substr(4), baud);
  throw LineError("transport '" + spec + "': serial:PATH or pty:PATH");
}

}  // namespace plc::profibus::link

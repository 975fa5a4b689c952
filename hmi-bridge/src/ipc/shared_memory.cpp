#include "plc/hmi/ipc/shared_memory.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>
#include <utility>

namespace plc::hmi::ipc {

namespace {
[[noreturn]] void fail(const char* what) {
  throw std::system_error(errno, std::generic_category(), what);
}
}  // namespace

Mapping::~Mapping() {
  if (data_) munmap(data_, size_);
  if (fd_ >= 0) close(fd_);
}

Mapping::Mapping(Mapping&& o) noexcept
    : data_(std::exchange(o.data_, nullptr)),
      size_(std::exchange(o.size_, 0)),
      fd_(std::exchange(o.fd_, -1)) {}

Mapping& Mapping::operator=(Mapping&& o) noexcept {
  if (this != &o) {
    this->~Mapping();
    data_ = std::exchange(o.data_, nullptr);
    size_ = std::exchange(o.size_, 0);
    fd_ = std::exchange(o.fd_, -1);
  }
  return *this;
}

Mapping Mapping::create(const char* name, std::size_t size) {
  Mapping m;
  // Close-on-exec: the supervisor hands plchmi the descriptors it means to
  // (dup2 to fixed numbers); nothing else inherits them.
  m.fd_ = memfd_create(name, MFD_CLOEXEC | MFD_ALLOW_SEALING);
  if (m.fd_ < 0) fail("memfd_create");
  if (ftruncate(m.fd_, off_t(size)) != 0) fail("ftruncate(memfd)");
  void* p = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED, m.fd_, 0);
  if (p == MAP_FAILED) fail("mmap(memfd)");
  m.data_ = static_cast<unsigned char*>(p);
  m.size_ = size;
  return m;
}

void Mapping::seal_future_writes() {
  if (fcntl(fd_, F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_FUTURE_WRITE | F_SEAL_SEAL) != 0)
    fail("fcntl(F_ADD_SEALS)");
}

Mapping Mapping::attach(int fd, bool writable, std::string& error) {
  Mapping m;
  struct stat st {};
  if (fstat(fd, &st) != 0) {
    error = "fd " + std::to_string(fd) + ": " + std::generic_category().message(errno);
    return m;
  }
  if (st.st_size <= 0) {
    error = "fd " + std::to_string(fd) + " is empty";
    return m;
  }
  const auto size = std::size_t(st.st_size);
  void* p = mmap(nullptr, size, writable ? PROT_READ | PROT_WRITE : PROT_READ, MAP_SHARED, fd, 0);
  if (p == MAP_FAILED) {
    error = "mmap(fd " + std::to_string(fd) + "): " + std::generic_category().message(errno);
    return m;
  }
  m.data_ = static_cast<unsigned char*>(p);
  m.size_ = size;
  return m;
}

}  // namespace plc::hmi::ipc

// Shared memory between plcrun and its HMI bridge process (plchmi): a
// memfd (memfd_create(2)) mapped by both. Two regions (hmi-bridge/README.md,
// "Process layout"):
//   state    written by plcrun only; sealed (F_SEAL_FUTURE_WRITE) once plcrun
//            has mapped it, so plchmi can map it read-only and nothing else
//            (a writable mapping, write(2), ftruncate: EPERM);
//   control  written by both: plchmi's command ring, its requests for
//            snapshots, the read position of the reply ring. plcrun trusts
//            nothing it reads there.
// plchmi gets the file descriptors by inheritance (fork+exec, fixed fd
// numbers) and maps them with Mapping::attach.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace plc::hmi::ipc {

class Mapping {
 public:
  Mapping() = default;
  ~Mapping();
  Mapping(Mapping&& o) noexcept;
  Mapping& operator=(Mapping&& o) noexcept;
  Mapping(const Mapping&) = delete;
  Mapping& operator=(const Mapping&) = delete;

  // A new memfd of `size` bytes (zeroed), mapped read-write. `name` shows
  // in /proc/PID/fd. Throws std::system_error.
  static Mapping create(const char* name, std::size_t size);
  // Seals the memfd: its size fixed, and no writable mapping or write(2)
  // from now on (this mapping stays writable). Throws std::system_error.
  void seal_future_writes();
  // Maps an inherited memfd: its whole size, read-only or read-write.
  // Does not take the descriptor over (the caller closes it). Empty, with
  // the reason in `error`, when it cannot.
  static Mapping attach(int fd, bool writable, std::string& error);

  [[nodiscard]] unsigned char* data() const { return data_; }
  [[nodiscard]] std::size_t size() const { return size_; }
  // The memfd (-1 for an attached mapping).
  [[nodiscard]] int fd() const { return fd_; }
  [[nodiscard]] explicit operator bool() const { return data_ != nullptr; }

 private:
  unsigned char* data_ = nullptr;
  std::size_t size_ = 0;
  int fd_ = -1;
};

}  // namespace plc::hmi::ipc

// A station's access to one PROFIBUS line (RS-485, half duplex). Backends:
// a serial port through termios (serial_line.hpp: a USB RS-485 adapter, a
// UART, or a pty another process made), a pty this process makes, and an
// in-memory bus for lockstep tests (mem_line.hpp).
//
// send() hands one whole telegram to the line and never blocks; receive()
// returns the bytes that arrived since (any split: the FDL deframer
// delimits telegrams). A station does not receive its own transmissions
// (an RS-485 adapter's receiver is off while it drives the line).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>

namespace plc::profibus::link {

struct LineCounters {
  std::uint64_t tx_telegrams = 0, tx_bytes = 0, rx_bytes = 0;
  std::uint64_t tx_dropped = 0;  // send() refused (queue full, no peer, an error)
  std::uint64_t rx_errors = 0;   // parity/framing errors the driver reported
};

class Line {
 public:
  virtual ~Line() = default;
  virtual bool send(std::span<const std::uint8_t> telegram) = 0;
  virtual std::size_t receive(std::span<std::uint8_t> buf) = 0;
  // A descriptor readable when receive() may return bytes; -1 without one.
  [[nodiscard]] virtual int fd() const { return -1; }
  // Discards what was received and not read (a new start after a reset).
  virtual void flush_input() {}
  [[nodiscard]] virtual const LineCounters& counters() const = 0;
  [[nodiscard]] virtual std::string describe() const = 0;
};

struct LineError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Opens a line from its text form (throws LineError with the reason):
//   serial:PATH   an existing tty (RS-485 adapter, UART, a pty's slave side),
//                 8E1 at `baud` (custom rates through termios2/BOTHER)
//   pty:PATH      a new pty; PATH becomes a symlink to its slave side, which
//                 the other station opens with serial:PATH
std::unique_ptr<Line> open_line(const std::string& spec, std::uint32_t baud);

}  // namespace plc::profibus::link

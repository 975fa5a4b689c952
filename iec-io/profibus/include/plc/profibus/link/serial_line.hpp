// A PROFIBUS line on a tty: a serial port (a USB RS-485 adapter, a UART
// with an RS-485 transceiver) or a pty.
//
// The port runs 8E1 (8 data bits, even parity, one stop bit: the PROFIBUS
// UART character) in raw mode, non-blocking; characters with a parity or
// framing error are dropped by the driver (IGNPAR) and the FDL deframer
// resynchronises. The rate is set with termios2 and BOTHER, so the
// non-standard PROFIBUS rates (45.45k, 93.75k, 187.5k, 1.5M, 3M, 6M, 12M)
// reach the driver as they are; whether the hardware makes them is the
// adapter's business (iec-io/profibus/README.md: what USB adapters and
// Linux UARTs allow). On a pty the rate and parity mean nothing.
//
// A pty made here (`pty:PATH`) keeps its own descriptor on the slave side
// open, so the master side never sees a hang-up while the other process is
// away (killed, restarting): what is sent then waits in the pty (or is
// dropped when full, counted), and a station opening PATH anew flushes it.
#pragma once

#include <string>

#include "plc/profibus/link/line.hpp"

namespace plc::profibus::link {

class SerialLine final : public Line {
 public:
  // Opens `path` (serial:) with 8E1 at `baud`; throws LineError.
  static std::unique_ptr<SerialLine> open_tty(const std::string& path, std::uint32_t baud);
  // Makes a pty and a symlink `link_path` to its slave side (pty:); throws LineError.
  static std::unique_ptr<SerialLine> make_pty(const std::string& link_path, std::uint32_t baud);
  ~SerialLine() override;

  bool send(std::span<const std::uint8_t> telegram) override;
  std::size_t receive(std::span<std::uint8_t> buf) override;
  [[nodiscard]] int fd() const override { return fd_; }
  void flush_input() override;
  [[nodiscard]] const LineCounters& counters() const override { return counters_; }
  [[nodiscard]] std::string describe() const override { return what_; }
  [[nodiscard]] bool is_pty() const { return pty_; }

 private:
  SerialLine() = default;
  int fd_ = -1;
  int hold_ = -1;  // our own descriptor on a pty's slave side
  bool pty_ = false;
  std::string link_;  // the symlink we made (removed on close)
  std::string what_;
  LineCounters counters_;
};

// Sets 8E1 raw at `baud` on a tty (termios2, BOTHER); false with errno set
// when the driver refuses.
bool set_line_mode(int fd, std::uint32_t baud);

}  // namespace plc::profibus::link

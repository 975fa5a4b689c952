// termios2 lives in <asm/termbits.h>, which clashes with glibc's
// <termios.h>: this file includes only the kernel's definitions.
#include <asm/termbits.h>
#include <linux/serial.h>
#include <sys/ioctl.h>

#include <cerrno>
#include <cstdint>

namespace plc::profibus::link {

bool set_line_mode(int fd, std::uint32_t baud) {
  struct termios2 t {};
  if (ioctl(fd, TCGETS2, &t) != 0) return false;
  t.c_iflag = INPCK | IGNPAR | IGNBRK;  // drop characters with parity/framing errors
  t.c_oflag = 0;
  t.c_lflag = 0;
  t.c_cflag &= ~static_cast<tcflag_t>(CBAUD | CSIZE | CSTOPB | PARODD | CRTSCTS);
  t.c_cflag |= BOTHER | CS8 | PARENB | CREAD | CLOCAL;
  t.c_ispeed = baud;
  t.c_ospeed = baud;
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  if (ioctl(fd, TCSETS2, &t) != 0) return false;
  // Ask the driver for low latency (FTDI: latency timer 1 ms instead of
  // 16); drivers without the flag refuse, which is no error here.
  struct serial_struct ss {};
  if (ioctl(fd, TIOCGSERIAL, &ss) == 0) {
    ss.flags |= ASYNC_LOW_LATENCY;
    (void)ioctl(fd, TIOCSSERIAL, &ss);
  }
  errno = 0;
  return true;
}

}  // namespace plc::profibus::link

// The serial line's mode (iec-io/profibus/include/plc/profibus/link/
// serial_line.hpp): 8E1 raw through termios2 with BOTHER, so every one of
// the ten PROFIBUS rates (EN 50170 vol. 2, 9.6 kbit/s .. 12 Mbit/s, the
// non-standard 45.45k, 93.75k, 187.5k, 1.5M, 3M, 6M, 12M too) reaches the
// driver as it is. Read back from a pty's slave side, which keeps what it
// is given (no hardware here: whether a UART makes the rate is the
// adapter's business, iec-io/profibus/README.md). The one thing a pty
// does not keep is the parity: Linux's pty_set_termios() clears PARENB
// (a pty is 8-bit clean), so even parity is not read back here.
//
// <asm/termbits.h> clashes with glibc's <termios.h>: this file includes
// only the kernel's definitions, as src/link/termios2.cpp does.
#include <asm/termbits.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cstdlib>

#include "plc/profibus/fdl/timing.hpp"
#include "plc/profibus/link/serial_line.hpp"

using namespace plc::profibus;

TEST(PbLineMode, EveryProfibusRateReachesTheTtyRaw8BitsOneStopBit) {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(master, 0);
  ASSERT_EQ(::grantpt(master), 0);
  ASSERT_EQ(::unlockpt(master), 0);
  const int tty = ::open(::ptsname(master), O_RDWR | O_NOCTTY | O_NONBLOCK);
  ASSERT_GE(tty, 0);
  ASSERT_EQ(fdl::baud_profiles().size(), 10u);
  for (const fdl::BaudProfile& p : fdl::baud_profiles()) {
    ASSERT_TRUE(link::set_line_mode(tty, p.baud)) << p.baud;
    struct termios2 t {};
    ASSERT_EQ(::ioctl(tty, TCGETS2, &t), 0);
    EXPECT_EQ(t.c_ospeed, p.baud);
    EXPECT_EQ(t.c_ispeed, p.baud);
    EXPECT_EQ(t.c_cflag & CBAUD, static_cast<tcflag_t>(BOTHER)) << p.baud;
    EXPECT_EQ(t.c_cflag & CSIZE, static_cast<tcflag_t>(CS8));
    EXPECT_FALSE(t.c_cflag & CSTOPB) << "one stop bit";
    EXPECT_FALSE(t.c_cflag & CRTSCTS);
    EXPECT_EQ(t.c_lflag & (ICANON | ECHO | ISIG), 0u) << "raw";
    EXPECT_EQ(t.c_oflag & OPOST, 0u);
    EXPECT_EQ(t.c_iflag & (IXON | IXOFF | ICRNL | ISTRIP), 0u) << "8 bits as they are";
    EXPECT_EQ(t.c_cc[VMIN], 0);
    EXPECT_EQ(t.c_cc[VTIME], 0);
  }
  ::close(tty);
  ::close(master);
}

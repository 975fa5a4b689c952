// The lines (iec-io/profibus/link): the in-memory bus, a pty made by one
// station and opened as a serial tty by the other (8E1 raw, termios2), the
// capture. Bounded loops on poll(), no sleeps.
#include <gtest/gtest.h>
#include <poll.h>

#include <vector>

#include "plc/profibus/fdl/deframer.hpp"
#include "plc/profibus/link/capture.hpp"
#include "plc/profibus/link/mem_line.hpp"
#include "plc/profibus/link/serial_line.hpp"
#include "runtime/test_helpers.hpp"

using namespace plc::profibus;
using Bytes = std::vector<std::uint8_t>;

namespace {

// Reads from `l` until `n` bytes came or `max_ms` passed.
Bytes read_bytes(link::Line& l, std::size_t n, int max_ms = 2000) {
  Bytes out;
  for (int i = 0; i < max_ms && out.size() < n; ++i) {
    pollfd p{l.fd(), POLLIN, 0};
    (void)poll(&p, 1, 1);
    std::array<std::uint8_t, 256> b{};
    const std::size_t k = l.receive(b);
    out.insert(out.end(), b.begin(), b.begin() + static_cast<std::ptrdiff_t>(k));
  }
  return out;
}

const Bytes kDiagReq{0x68, 0x05, 0x05, 0x68, 0x85, 0x82, 0x6D, 0x3C, 0x3E, 0xEE, 0x16};
const Bytes kSc{0xE5};

}  // namespace

TEST(PbLink, MemBusDeliversToTheOthersAndACutLineToNoOne) {
  auto bus = link::MemBus::create();
  auto a = bus->attach(), b = bus->attach(), c = bus->attach();
  a->send(kDiagReq);
  std::array<std::uint8_t, 64> buf{};
  EXPECT_EQ(b->receive(buf), kDiagReq.size());
  EXPECT_EQ(c->receive(buf), kDiagReq.size());
  EXPECT_EQ(a->receive(buf), 0u) << "not its own telegram";
  bus->set_cut(true);
  a->send(kDiagReq);
  EXPECT_EQ(b->receive(buf), 0u);
  bus->set_cut(false);
  a->send(kSc);
  EXPECT_EQ(b->receive(buf), 1u);
}

// A pty made by the master (pty:PATH) and opened by the slave as a serial
// tty (serial:PATH): raw 8-bit both ways (0x11/0x13 are no XON/XOFF, 0x0D
// no CR), the slave side closed and opened again without a hang-up on the
// master side, and what the master sent meanwhile flushed at the new open.
TEST(PbLink, PtyBothWaysRawAndAReopenedSlaveSide) {
  const std::string path = plctest::temp_path("pb_link_pty");
  auto m = link::SerialLine::make_pty(path, 1500000);
  EXPECT_TRUE(m->is_pty());
  auto s = link::SerialLine::open_tty(path, 1500000);
  EXPECT_TRUE(s->is_pty());
  const Bytes odd{0x68, 0x07, 0x07, 0x68, 0x05, 0x01, 0x7D, 0x11, 0x13, 0x0D, 0x0A, 0x00, 0x16};
  ASSERT_TRUE(m->send(odd));
  EXPECT_EQ(read_bytes(*s, odd.size()), odd);
  ASSERT_TRUE(s->send(kSc));
  EXPECT_EQ(read_bytes(*m, 1), kSc);
  s.reset();  // the slave process is gone
  EXPECT_TRUE(m->send(kDiagReq)) << "no hang-up: our own descriptor holds the slave side";
  pollfd p{m->fd(), POLLIN, 0};
  EXPECT_EQ(poll(&p, 1, 0), 0) << "no POLLHUP on the master side";
  auto s2 = link::SerialLine::open_tty(path, 1500000);
  // Bytes in a pty are there at once: 50 ms is long enough to see them.
  EXPECT_TRUE(read_bytes(*s2, 1, 50).empty()) << "the stale request was flushed";
  ASSERT_TRUE(m->send(kSc));
  EXPECT_EQ(read_bytes(*s2, 1), kSc);
  m.reset();
  EXPECT_EQ(::access(path.c_str(), F_OK), -1) << "the symlink goes with the pty";
}

TEST(PbLink, OpenErrorsSayWhy) {
  try {
    link::open_line("serial:/nonexistent/tty", 19200);
    FAIL();
  } catch (const link::LineError& e) {
    EXPECT_NE(std::string(e.what()).find("serial:/nonexistent/tty: No such file"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(link::open_line("tcp:1", 19200), link::LineError);
  // A regular file is never replaced by the pty's symlink.
  const std::string f = plctest::write_temp("pb_link_file", "x");
  EXPECT_THROW(link::SerialLine::make_pty(f, 19200), link::LineError);
}

// The capture: a decoded line per telegram and a pcap with link type 257.
TEST(PbLink, CaptureWritesDecodedTextAndPcap257) {
  const std::string txt = plctest::temp_path("pb_cap.txt"),
                    pcap = plctest::temp_path("pb_cap.pcap");
  {
    link::Capture c(txt, pcap);
    fdl::Telegram t;
    ASSERT_EQ(fdl::decode(kDiagReq, t).status, fdl::DecodeStatus::Ok);
    c.record(1'500'000, true, kDiagReq, t);
    ASSERT_EQ(fdl::decode(kSc, t).status, fdl::DecodeStatus::Ok);
    c.record(2'000'000, false, kSc, t);
    // An FDL status answer (OK, no data) is no Data_Exchange.
    const Bytes status{0x10, 0x02, 0x05, 0x00, 0x07, 0x16};
    ASSERT_EQ(fdl::decode(status, t).status, fdl::DecodeStatus::Ok);
    c.record(3'000'000, false, status, t);
    c.flush();
  }
  const std::string text = plctest::read_file(txt);
  EXPECT_NE(text.find("1.500000 tx SD2 2->5 SRD_high DSAP 60 SSAP 62 Slave_Diag | 68 05 05 68"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("2.000000 rx SC | E5"), std::string::npos) << text;
  EXPECT_NE(text.find("3.000000 rx SD1 5->2 OK (slave) | 10 02 05 00 07 16"), std::string::npos)
      << text;
  const std::string p = plctest::read_file(pcap);
  ASSERT_GE(p.size(), 24u + 16 + 11 + 16 + 1);
  EXPECT_EQ(static_cast<std::uint8_t>(p[20]), 257 & 0xFF);  // network, little-endian
  EXPECT_EQ(static_cast<std::uint8_t>(p[21]), 257 >> 8);
}

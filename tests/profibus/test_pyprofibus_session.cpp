// An independent DP master against our DP slave: pyprofibus (mbuesch/
// pyprofibus e7c9815, GPL-2.0+; peers.md) ran as master 2 on one side of a
// socat pty pair (19.2 kbit/s, its serial PHY with pyserial 3.5), with
// build/bin/dpslavesim hosting the PR5510 at address 5 on the other,
// pyprofibus reading our iec-io/profibus/gsd/GWT_5610.gsd with its own GSD
// parser (module "8 Byte I/O Konsistent" -> Cfg B7, User_Prm_Data empty).
// It went through its start-up and 2037 Data_Exchanges in 8 s. The bytes
// it sent (its PHY debug log) are replayed here, in order, against our
// slave, and our answers are checked against the ones pyprofibus took.
// Run by hand in a session; none of its code is here.
#include <gtest/gtest.h>

#include "pb_rig.hpp"

using namespace pbtest;

namespace {
using Bytes = std::vector<std::uint8_t>;

Bytes send_raw(RawMaster& m, const Bytes& req) {
  m.line->send(req);
  m.now += 1ms;
  m.slave->tick(m.now);
  std::array<std::uint8_t, 512> in{};
  const std::size_t n = m.line->receive(in);
  return {in.begin(), in.begin() + n};
}
}  // namespace

TEST(PyprofibusSession, StartUpAndDataExchangeAsPyprofibusSentThem) {
  RawMaster m(pr1721_slave(5));
  // FDL status (its live list): OK, station type slave.
  EXPECT_EQ(send_raw(m, {0x10, 0x05, 0x02, 0x49, 0x50, 0x16}),
            (Bytes{0x10, 0x02, 0x05, 0x00, 0x07, 0x16}));
  // Slave_Diag, FCB=1 FCV=0: Station_Not_Ready, Prm_Req, no master yet.
  EXPECT_EQ(
      send_raw(m, {0x68, 0x05, 0x05, 0x68, 0x85, 0x82, 0x6D, 0x3C, 0x3E, 0xEE, 0x16}),
      (Bytes{0xA2, 0x82, 0x85, 0x08, 0x3E, 0x3C, 0x02, 0x05, 0x00, 0xFF, 0x56, 0x10, 0xF5, 0x16}));
  // Set_Prm: Lock_Req + WD_On, WD 50 x 1 x 10 ms, minTSDR 0, Ident 0x5610, group 1.
  EXPECT_EQ(send_raw(m, {0x68, 0x0C, 0x0C, 0x68, 0x85, 0x82, 0x5D, 0x3D, 0x3E, 0x88, 0x32, 0x01,
                         0x00, 0x56, 0x10, 0x01, 0x01, 0x16}),
            (Bytes{0xE5}));
  // Chk_Cfg B7, built by pyprofibus from our GSD.
  EXPECT_EQ(send_raw(m, {0x68, 0x06, 0x06, 0x68, 0x85, 0x82, 0x7D, 0x3E, 0x3E, 0xB7, 0xB7, 0x16}),
            (Bytes{0xE5}));
  // Slave_Diag: ready, WD_On, master 2.
  EXPECT_EQ(
      send_raw(m, {0x68, 0x05, 0x05, 0x68, 0x85, 0x82, 0x5D, 0x3C, 0x3E, 0xDE, 0x16}),
      (Bytes{0xA2, 0x82, 0x85, 0x08, 0x3E, 0x3C, 0x00, 0x0C, 0x00, 0x02, 0x56, 0x10, 0xFD, 0x16}));
  EXPECT_EQ(m.slave->state(), pb::slave::SlaveState::DataExch);
  // Data_Exchange, FCB alternating: 8 bytes out, 8 bytes in (SD3, DL).
  for (int i = 0; i < 4; ++i) {
    const Bytes req = (i % 2 == 0) ? Bytes{0xA2, 0x05, 0x02, 0x7D, 0x00, 0x00, 0x00,
                                           0x00, 0x12, 0x00, 0x00, 0x80, 0x16, 0x16}
                                   : Bytes{0xA2, 0x05, 0x02, 0x5D, 0x00, 0x00, 0x00,
                                           0x00, 0x12, 0x00, 0x00, 0x80, 0xF6, 0x16};
    const Bytes a = send_raw(m, req);
    ASSERT_EQ(a.size(), 14u);
    EXPECT_EQ(Bytes(a.begin(), a.begin() + 4), (Bytes{0xA2, 0x02, 0x05, 0x08}));
    EXPECT_EQ(a.back(), 0x16);
  }
  EXPECT_EQ(m.slave->counters().data_exchanges, 4u);
  EXPECT_EQ(m.slave->counters().repeats, 0u);
  EXPECT_EQ(m.model->last_outputs, (Bytes{0, 0, 0, 0, 0x12, 0, 0, 0x80}));
}

// The DP-V0 slave state machine (EN 50170 vol. 2 DP, slave: Wait_Prm ->
// Wait_Cfg -> Data_Exch) with the PR1721/31's identity and modules
// (sartorius-pr1721.md §1.2), driven telegram by telegram: every bit of
// Station_Status_1/2 it can set, the watchdog, Global_Control Freeze/Sync,
// the FCB repetition.
#include <gtest/gtest.h>

#include "pb_rig.hpp"

using namespace pbtest;
using pb::slave::SlaveState;

TEST(DpSlave, PowerOnDiagnosisIsPrmReqAndStationNotReady) {
  RawMaster m(pr1721_slave(5));
  const dp::Diagnosis d = m.diag();
  EXPECT_EQ(d.status1, dp::kDiag1StationNotReady);
  EXPECT_EQ(d.status2, dp::kDiag2PrmReq | dp::kDiag2Always1);
  EXPECT_EQ(d.master, 0xFF);
  EXPECT_EQ(d.ident, 0x5610);
  EXPECT_EQ(m.slave->state(), SlaveState::WaitPrm);
}

TEST(DpSlave, StartUpToDataExchangeAndTheWindowBothWays) {
  RawMaster m(pr1721_slave(5));
  m.start();
  EXPECT_EQ(m.slave->state(), SlaveState::DataExch);
  dp::Diagnosis d = m.diag();
  EXPECT_EQ(d.status1, 0);
  EXPECT_EQ(d.status2, dp::kDiag2Always1 | dp::kDiag2WdOn);
  EXPECT_EQ(d.master, 1);
  EXPECT_TRUE(d.ready());
  const auto a = m.data_exchange({0, 1, 2, 3, 4, 5, 6, 7});
  ASSERT_TRUE(a);
  EXPECT_EQ(a->function(), fdl::kResDataLow);
  ASSERT_EQ(a->length, 8);
  m.data_exchange({0, 1, 2, 3, 4, 5, 6, 7});
  EXPECT_EQ(m.model->last_outputs, (std::vector<std::uint8_t>{0, 1, 2, 3, 4, 5, 6, 7}));
}

// Prm_Fault: a foreign Ident_Number, user parameters the GSD does not have
// (User_Prm_Data_Len = 0), Freeze without support.
TEST(DpSlave, PrmFaultForIdentUserParametersAndUnsupportedModes) {
  for (int k = 0; k < 3; ++k) {
    auto c = pr1721_slave(5);
    if (k == 2) c.freeze_supported = false;
    RawMaster m(c);
    dp::SetPrm p;
    p.ident = k == 0 ? 0x1234 : 0x5610;
    if (k == 1) p.user = {0x00};
    if (k == 2) p.station_status |= dp::kPrmFreezeReq;
    EXPECT_TRUE(m.set_prm(p)) << "acknowledged with SC all the same";
    const dp::Diagnosis d = m.diag();
    EXPECT_EQ(d.status1, dp::kDiag1StationNotReady | dp::kDiag1PrmFault) << k;
    EXPECT_TRUE(d.status2 & dp::kDiag2PrmReq);
    EXPECT_EQ(m.slave->state(), SlaveState::WaitPrm);
  }
}

// Cfg_Fault: 16 bytes for a slave set to 8; a module the GSD does not list;
// more than Max_Module = 4. Back to Wait_Prm. Combinations that add up are
// taken: 2 x "4 Word I/O" for 16 bytes.
TEST(DpSlave, CfgFaultAndTheModuleCombinationsOfAModularStation) {
  {
    RawMaster m(pr1721_slave(5));
    m.start();  // B7 on an 8-byte slave: fine
    for (const std::vector<std::uint8_t>& bad :
         {std::vector<std::uint8_t>{0xBF}, {0x13}, {0xB7, 0xB7}}) {
      dp::SetPrm p;
      p.ident = 0x5610;
      ASSERT_TRUE(m.set_prm(p));
      ASSERT_TRUE(m.chk_cfg(bad));
      const dp::Diagnosis d = m.diag();
      EXPECT_EQ(d.status1, dp::kDiag1StationNotReady | dp::kDiag1CfgFault) << dp::hex(bad);
      EXPECT_EQ(m.slave->state(), SlaveState::WaitPrm);
    }
  }
  RawMaster m16(pr1721_slave(5, 16));
  dp::SetPrm p;
  p.ident = 0x5610;
  ASSERT_TRUE(m16.set_prm(p));
  ASSERT_TRUE(m16.chk_cfg({0xF3, 0x73}));
  EXPECT_EQ(m16.slave->state(), SlaveState::DataExch);
  RawMaster m64(pr1721_slave(5, 64));
  ASSERT_TRUE(m64.set_prm(p));
  ASSERT_TRUE(m64.chk_cfg({0xB7, 0xB7, 0xBF, 0xFF}));
  EXPECT_EQ(m64.slave->state(), SlaveState::DataExch);
  ASSERT_TRUE(m64.set_prm(p));
  ASSERT_TRUE(m64.chk_cfg({0xBF, 0xBF, 0xBF, 0xB7, 0xB7}));
  EXPECT_EQ(m64.slave->state(), SlaveState::WaitPrm) << "five modules";
}

// Master_Lock: another master asking a slave locked by master 1; its
// Set_Prm is acknowledged and ignored; its Data_Exchange refused (RS).
TEST(DpSlave, MasterLockForASecondMaster) {
  RawMaster m(pr1721_slave(5));
  m.start();
  const dp::Diagnosis other = m.diag(7);
  EXPECT_TRUE(other.status1 & dp::kDiag1MasterLock);
  EXPECT_EQ(other.master, 1);
  dp::SetPrm p;
  p.ident = 0x5610;
  EXPECT_TRUE(m.set_prm(p, 7));
  EXPECT_EQ(m.slave->master(), 1);
  EXPECT_EQ(m.slave->state(), SlaveState::DataExch);
  const auto a = m.exchange(m.srd(-1, std::vector<std::uint8_t>(8, 0), 7));
  ASSERT_TRUE(a);
  EXPECT_EQ(a->function(), fdl::kResNoService);
  EXPECT_FALSE(m.diag().status1 & dp::kDiag1MasterLock) << "not for its own master";
}

// Data_Exchange before the slave is parametrised, or of the wrong length:
// RS (no service activated).
TEST(DpSlave, DataExchangeOutsideDataExchIsRefusedWithRs) {
  RawMaster m(pr1721_slave(5));
  auto a = m.data_exchange(std::vector<std::uint8_t>(8, 0));
  ASSERT_TRUE(a);
  EXPECT_EQ(a->function(), fdl::kResNoService);
  m.start();
  a = m.data_exchange(std::vector<std::uint8_t>(7, 0));
  ASSERT_TRUE(a);
  EXPECT_EQ(a->function(), fdl::kResNoService);
}

// Stat_Diag and Ext_Diag: the slave answers Data_Exchange with DH (high
// priority: read my diagnosis); the diagnosis carries the bits and blocks.
// Extended diagnosis vector: Rahix/profirust src/dp/diagnostics.rs
// test_diag_iter (identifier block 44 00 01 00, channel 88 41 21, device 04
// 10 20 30).
TEST(DpSlave, StatDiagAndExtDiagAnswerHighPriority) {
  RawMaster m(pr1721_slave(5));
  m.start();
  m.slave->faults().stat_diag = true;
  m.slave->faults().ext = {0x44, 0x00, 0x01, 0x00, 0x88, 0x41, 0x21, 0x04, 0x10, 0x20, 0x30};
  const auto a = m.data_exchange(std::vector<std::uint8_t>(8, 0));
  ASSERT_TRUE(a);
  EXPECT_EQ(a->function(), fdl::kResDataHigh);
  const dp::Diagnosis d = m.diag();
  EXPECT_EQ(d.status1, dp::kDiag1ExtDiag);
  EXPECT_TRUE(d.status2 & dp::kDiag2StatDiag);
  EXPECT_FALSE(d.ready());
  EXPECT_EQ(dp::ext_diag_text(d.ext),
            "identifier diag: modules 8; channel diag: module 8 channel 1 in error 1; device "
            "diag: 10 20 30");
}

// Watchdog (Set_Prm: 10 x 1 x 10 ms = 100 ms): silence from the master
// beyond it takes the slave back to Wait_Prm, clears its outputs and
// releases the lock (Prm_Req); telegrams within it keep it in Data_Exch.
TEST(DpSlave, WatchdogExpiryClearsOutputsAndWantsParametersAgain) {
  RawMaster m(pr1721_slave(5));
  m.start();
  for (int i = 0; i < 10; ++i) m.data_exchange({0, 0, 0, 0, 0x12, 0, 0, 0x80}, 50ms);
  EXPECT_EQ(m.slave->state(), SlaveState::DataExch);
  EXPECT_EQ(m.model->last_outputs[7], 0x80);
  m.now += 101ms;
  m.slave->tick(m.now);
  EXPECT_EQ(m.slave->state(), SlaveState::WaitPrm);
  EXPECT_EQ(m.slave->counters().watchdog_expiries, 1u);
  EXPECT_EQ(m.model->connection_losses, 1);
  m.now += 1ms;
  m.slave->tick(m.now);
  EXPECT_EQ(m.model->last_outputs, std::vector<std::uint8_t>(8, 0)) << "outputs cleared";
  const dp::Diagnosis d = m.diag();
  EXPECT_TRUE(d.status2 & dp::kDiag2PrmReq);
  EXPECT_EQ(d.master, 0xFF);
  EXPECT_FALSE(d.status2 & dp::kDiag2WdOn);
}

// Global_Control (DP §8.3.4.7): Freeze holds the inputs at the moment of the
// command (each Freeze takes a new picture), Unfreeze returns to live
// inputs; Sync applies outputs only at the next Sync, Unsync returns to
// live outputs; Clear_Data clears them; another group is not addressed.
TEST(DpSlave, GlobalControlFreezeSyncClearAndGroups) {
  RawMaster m(pr1721_slave(5));
  m.start();
  m.data_exchange(std::vector<std::uint8_t>(8, 0));
  m.global_control(dp::kGcFreeze, 0x01);
  EXPECT_TRUE(m.slave->frozen());
  const auto f1 = m.data_exchange(std::vector<std::uint8_t>(8, 0));
  const auto f2 = m.data_exchange(std::vector<std::uint8_t>(8, 0));
  ASSERT_TRUE(f1 && f2);
  EXPECT_EQ(f1->data[0], f2->data[0]) << "frozen: the step counter stands still";
  EXPECT_TRUE(m.diag().status2 & dp::kDiag2FreezeMode);
  m.global_control(dp::kGcFreeze, 0x01);
  const auto f3 = m.data_exchange(std::vector<std::uint8_t>(8, 0));
  EXPECT_NE(f3->data[0], f1->data[0]) << "a new Freeze takes a new picture";
  m.global_control(dp::kGcUnfreeze, 0x01);
  EXPECT_FALSE(m.slave->frozen());

  m.global_control(dp::kGcSync, 0x02);  // group 2: not ours
  EXPECT_FALSE(m.slave->synced());
  m.global_control(dp::kGcSync, 0x00);  // all groups
  EXPECT_TRUE(m.slave->synced());
  m.data_exchange({1, 2, 3, 4, 5, 6, 7, 8});
  EXPECT_EQ(m.slave->applied_outputs()[0], 0) << "held until the next Sync";
  m.global_control(dp::kGcSync, 0x01);
  EXPECT_EQ(m.slave->applied_outputs()[0], 1);
  m.data_exchange({9, 9, 9, 9, 9, 9, 9, 9});
  EXPECT_EQ(m.slave->applied_outputs()[0], 1);
  EXPECT_TRUE(m.diag().status2 & dp::kDiag2SyncMode);
  m.global_control(dp::kGcUnsync, 0x01);
  EXPECT_EQ(m.slave->applied_outputs()[0], 9);
  m.global_control(dp::kGcClearData, 0x01);
  EXPECT_EQ(m.slave->applied_outputs()[0], 0);
}

// Not_Supported: Freeze to a slave whose Set_Prm did not ask for it.
TEST(DpSlave, FreezeWithoutTheSetPrmRequestIsNotSupported) {
  RawMaster m(pr1721_slave(5));
  m.start(dp::kPrmLockReq);
  m.global_control(dp::kGcFreeze, 0);
  EXPECT_FALSE(m.slave->frozen());
  EXPECT_TRUE(m.diag().status1 & dp::kDiag1NotSupported);
}

// FCB (IEC 61158-4-3: frame count bit): a request repeated with FCV set and
// the same FCB (its answer was lost) gets the same answer again and is not
// executed twice; the next FCB is a new request.
TEST(DpSlave, RepeatedFrameCountBitGetsTheLastAnswerAgain) {
  RawMaster m(pr1721_slave(5));
  m.start();
  fdl::Telegram t = m.srd(-1, std::vector<std::uint8_t>{1, 1, 1, 1, 1, 1, 1, 1});
  t.fc |= fdl::kFcFcv | fdl::kFcFcb;  // start() sent FCB 0: this is new
  const auto a1 = m.exchange(t);
  const auto a2 = m.exchange(t);
  ASSERT_TRUE(a1 && a2);
  EXPECT_EQ(a1->data[0], a2->data[0]);
  EXPECT_EQ(m.slave->counters().data_exchanges, 1u);
  EXPECT_EQ(m.slave->counters().repeats, 1u);
  t.fc &= static_cast<std::uint8_t>(~fdl::kFcFcb);
  m.exchange(t);
  EXPECT_EQ(m.slave->counters().data_exchanges, 2u);
}

// FDL status (the GAP update of a master): a slave answers OK, station type
// slave ([R] profirust: 10 02 22 00 24 16 from address 34 to 2).
TEST(DpSlave, AnswersFdlStatusAsASlave) {
  RawMaster m(pr1721_slave(34));
  m.address = 2;
  const auto a = m.exchange(fdl::make_data(34, 2, fdl::kFcRequest | fdl::kReqFdlStatus, -1, -1));
  ASSERT_TRUE(a);
  std::array<std::uint8_t, 16> b{};
  const std::size_t n = fdl::encode(*a, b);
  EXPECT_EQ(std::vector<std::uint8_t>(b.begin(), b.begin() + n),
            (std::vector<std::uint8_t>{0x10, 0x02, 0x22, 0x00, 0x24, 0x16}));
}

// Silent (a pulled plug): no answer at all.
TEST(DpSlave, SilentSlaveAnswersNothing) {
  RawMaster m(pr1721_slave(5));
  m.slave->faults().silent = true;
  EXPECT_FALSE(m.exchange(m.srd(dp::kSapSlaveDiag)).has_value());
}

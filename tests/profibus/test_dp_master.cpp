// The DP master class 1 (EN 50170 vol. 2 DP, master: Slave_Diag -> Set_Prm
// -> Chk_Cfg -> Slave_Diag -> Data_Exchange) against our DP slave on the
// in-memory line in lockstep virtual time: the start-up, its reaction to
// each diagnosis bit, the watchdog on both sides, retries and a lost
// slave, Global_Control, the token and the GAP update.
#include <gtest/gtest.h>

#include "pb_rig.hpp"

using namespace pbtest;
using pb::master::SlaveState;

TEST(DpMaster, StartsUpAndExchangesDataEveryCycle) {
  Rig r;
  SlaveNode& n = r.add_slave(pr1721_slave(5));
  const std::size_t d = r.master->add(pr1721_entry(5));
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 100ms))
      << r.master->diagnostics(d);
  EXPECT_EQ(r.master->link(d).live_state(), io::DeviceState::Online);
  EXPECT_EQ(n.slave->state(), pb::slave::SlaveState::DataExch);
  r.master->outputs(d)[5] = 0x42;
  r.run_for(20ms);
  EXPECT_EQ(n.model->last_outputs[5], 0x42);
  EXPECT_EQ(r.master->inputs(d)[5], 0x42) << "the echo came back";
  // One Data_Exchange per 2 ms cycle.
  EXPECT_GE(r.master->counters(d).data_exchanges, 9u);
  EXPECT_LE(r.master->counters(d).data_exchanges, 11u);
  EXPECT_EQ(r.master->counters(d).startups, 1u);
  EXPECT_GT(r.master->counters().tokens, 9u);
  EXPECT_EQ(r.master->last_diagnosis(d).status2, dp::kDiag2Always1 | dp::kDiag2WdOn);
}

// Station_Non_Existent: no answer to the first Slave_Diag and its retries
// (max_retry_limit 1 at 1.5 Mbit/s): the slave is lost, its diagnosis says
// so (as a device alarm for FBs), and it is tried again after `retry`.
TEST(DpMaster, NoSlaveAtTheAddressIsStationNonExistent) {
  Rig r;
  const std::size_t d = r.master->add(pr1721_entry(9));
  r.run_for(50ms);
  EXPECT_EQ(r.master->state(d), SlaveState::Waiting);
  EXPECT_EQ(r.master->last_diagnosis(d).status1, dp::kDiag1StationNonExistent);
  const io::DeviceAlarm a = r.master->link(d).last_alarm();
  EXPECT_GE(a.count, 1u);
  EXPECT_EQ(a.data >> 24, dp::kDiag1StationNonExistent);
  EXPECT_TRUE(a.appears);
  EXPECT_EQ(r.master->counters(d).retries, 1u) << "max_retry_limit 1";
  r.run_for(100ms);
  EXPECT_EQ(r.master->counters(d).startups, 2u) << "tried again after retry";
}

TEST(DpMaster, ForeignIdentNumberIsAFault) {
  Rig r;
  auto c = pr1721_slave(5);
  c.ident = 0x0815;
  r.add_slave(c);
  const std::size_t d = r.master->add(pr1721_entry(5));
  r.run_for(20ms);
  EXPECT_EQ(r.master->state(d), SlaveState::Fault);
  EXPECT_EQ(r.master->link(d).live_state(), io::DeviceState::Fault);
  EXPECT_NE(r.master->diagnostics(d).find("Ident_Number 0x0815, configured 0x5610"),
            std::string::npos);
}

TEST(DpMaster, PrmFaultIsReportedAndRetried) {
  Rig r;
  r.add_slave(pr1721_slave(5));
  auto e = pr1721_entry(5);
  e.prm.user = {0x01};  // the GSD has no user parameters
  const std::size_t d = r.master->add(e);
  r.run_for(20ms);
  EXPECT_EQ(r.master->state(d), SlaveState::Fault);
  EXPECT_TRUE(r.master->last_diagnosis(d).status1 & dp::kDiag1PrmFault);
  EXPECT_NE(r.master->diagnostics(d).find("Prm_Fault"), std::string::npos);
  EXPECT_TRUE(r.master->link(d).last_alarm().appears);
  r.run_for(100ms);
  EXPECT_EQ(r.master->counters(d).prm_faults, 2u) << "tried again after retry";
}

TEST(DpMaster, CfgFaultNamesTheRefusedConfiguration) {
  Rig r;
  r.add_slave(pr1721_slave(5));
  auto e = pr1721_entry(5);
  e.cfg = {0xBF};
  e.input_bytes = e.output_bytes = 16;
  const std::size_t d = r.master->add(e);
  r.run_for(20ms);
  EXPECT_EQ(r.master->state(d), SlaveState::Fault);
  EXPECT_NE(r.master->diagnostics(d).find("Cfg_Fault: the slave refuses Chk_Cfg BF"),
            std::string::npos)
      << r.master->diagnostics(d);
}

TEST(DpMaster, MasterLockedSlaveIsNotTaken) {
  Rig r;
  SlaveNode& n = r.add_slave(pr1721_slave(5));
  // Master 7 parametrised the slave first (from another line station).
  auto other = r.bus->attach();
  dp::SetPrm p;
  p.ident = 0x5610;
  const auto prm = p.encode();
  std::array<std::uint8_t, fdl::kMaxTelegram> b{};
  other->send({b.data(), fdl::encode(fdl::make_data(5, 7, fdl::kFcRequest | fdl::kReqSrdHigh,
                                                    dp::kSapSetPrm, dp::kSapMaster, prm),
                                     b)});
  n.slave->tick(r.now);
  ASSERT_EQ(n.slave->master(), 7);
  const std::size_t d = r.master->add(pr1721_entry(5));
  r.run_for(10ms);
  EXPECT_EQ(r.master->state(d), SlaveState::Fault);
  EXPECT_NE(r.master->diagnostics(d).find("Master_Lock: parametrised by master 7"),
            std::string::npos);
}

// Stat_Diag: the slave has no valid data: the master stops Data_Exchange,
// the device is Offline for FBs, and the master reads the diagnosis until
// the bit clears; then it exchanges data again without a new start-up.
TEST(DpMaster, StatDiagSuspendsDataExchangeUntilItClears) {
  Rig r;
  SlaveNode& n = r.add_slave(pr1721_slave(5));
  const std::size_t d = r.master->add(pr1721_entry(5));
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 100ms));
  n.slave->faults().stat_diag = true;
  r.run_for(10ms);
  EXPECT_EQ(r.master->state(d), SlaveState::Starting);
  EXPECT_EQ(r.master->link(d).live_state(), io::DeviceState::Offline);
  EXPECT_EQ(r.master->inputs(d)[0], 0) << "inputs read 0";
  const auto dx = r.master->counters(d).data_exchanges;
  r.run_for(10ms);
  EXPECT_EQ(r.master->counters(d).data_exchanges, dx);
  n.slave->faults().stat_diag = false;
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 20ms));
  EXPECT_EQ(r.master->counters(d).startups, 1u);
}

// Ext_Diag: DH to Data_Exchange, the master reads the diagnosis, FBs get it
// as a device alarm (Ext_Diag in the first byte), the HMI line shows the
// decoded blocks; data exchange goes on (Ext_Diag is no fault).
TEST(DpMaster, ExtendedDiagnosisReachesFbsAndTheHmiLine) {
  Rig r;
  SlaveNode& n = r.add_slave(pr1721_slave(5));
  const std::size_t d = r.master->add(pr1721_entry(5));
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 100ms));
  const auto before = r.master->link(d).last_alarm().count;
  n.slave->faults().ext = {0x04, 0x10, 0x20, 0x30};
  r.run_for(10ms);
  const io::DeviceAlarm a = r.master->link(d).last_alarm();
  EXPECT_GT(a.count, before);
  EXPECT_EQ(a.data >> 24, dp::kDiag1ExtDiag);
  EXPECT_TRUE(a.appears);
  EXPECT_NE(r.master->diagnostics(d).find("Ext_Diag"), std::string::npos);
  EXPECT_NE(r.master->diagnostics(d).find("device diag: 10 20 30"), std::string::npos);
}

// Watchdog, slave side: the master stalls past the slave's watchdog (100
// ms): the slave clears its outputs and falls back to Wait_Prm; the master,
// back, gets RS to Data_Exchange and parametrises it again by itself.
TEST(DpMaster, SlaveWatchdogExpiryIsRecoveredByANewStartUp) {
  Rig r;
  SlaveNode& n = r.add_slave(pr1721_slave(5));
  const std::size_t d = r.master->add(pr1721_entry(5, 100));
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 100ms));
  r.master->outputs(d)[3] = 7;
  r.run_for(10ms);
  ASSERT_EQ(n.model->last_outputs[3], 7);
  r.master_running = false;
  r.run_for(150ms);
  EXPECT_EQ(n.slave->state(), pb::slave::SlaveState::WaitPrm);
  EXPECT_EQ(n.model->last_outputs[3], 0) << "outputs cleared by the slave's watchdog";
  r.master_running = true;
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 50ms))
      << r.master->diagnostics(d);
  EXPECT_EQ(r.master->counters(d).startups, 2u);
  EXPECT_EQ(r.master->counters(d).refused, 1u) << "the RS that showed the loss";
  r.run_for(10ms);
  EXPECT_EQ(n.model->last_outputs[3], 7);
}

// Watchdog, master side: the slave stops answering (a pulled plug): after
// the slot time and max_retry repetitions it is lost, its inputs read 0,
// FBs see it Offline; the slave's own watchdog clears its outputs; the line
// back, the master parametrises it again by itself.
TEST(DpMaster, LostSlaveReadsZeroAndIsParametrisedAgain) {
  Rig r;
  SlaveNode& n = r.add_slave(pr1721_slave(5));
  const std::size_t d = r.master->add(pr1721_entry(5, 100));
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 100ms));
  r.master->outputs(d)[3] = 7;
  r.run_for(10ms);
  ASSERT_NE(r.master->inputs(d)[0], 0);
  r.bus->set_cut(true);
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) != SlaveState::Online; }, 10ms));
  EXPECT_EQ(r.master->link(d).live_state(), io::DeviceState::Offline);
  const auto in = r.master->inputs(d);
  EXPECT_EQ(std::vector<std::uint8_t>(in.begin(), in.end()), std::vector<std::uint8_t>(8, 0));
  EXPECT_EQ(r.master->counters(d).losses, 1u);
  r.run_for(150ms);
  EXPECT_EQ(n.slave->state(), pb::slave::SlaveState::WaitPrm) << "the slave's watchdog";
  EXPECT_EQ(n.model->last_outputs[3], 0);
  r.bus->set_cut(false);
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 200ms));
  r.run_for(10ms);
  EXPECT_EQ(n.model->last_outputs[3], 7);
}

// A killed and restarted slave (a new process: Wait_Prm, no FCB history).
TEST(DpMaster, RestartedSlaveIsTakenBackIntoDataExchange) {
  Rig r;
  SlaveNode& n = r.add_slave(pr1721_slave(5));
  const std::size_t d = r.master->add(pr1721_entry(5));
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 100ms));
  n.running = false;
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) != SlaveState::Online; }, 10ms));
  auto m = std::make_unique<EchoModel>(8);
  n.model = m.get();
  n.slave = std::make_unique<pb::slave::DpSlave>(pr1721_slave(5), std::move(m), *n.line);
  n.running = true;
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 200ms));
}

// Global_Control from the master: Freeze/Sync to group 1 reach the slave
// (SDN broadcast, no answer), the diagnosis shows Freeze_Mode/Sync_Mode.
TEST(DpMaster, GlobalControlFreezeAndSyncForAGroup) {
  Rig r;
  SlaveNode& n = r.add_slave(pr1721_slave(5));
  const std::size_t d = r.master->add(pr1721_entry(5));
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 100ms));
  r.master->global_control(dp::kGcFreeze | dp::kGcSync, 0x01);
  r.run_for(4ms);
  EXPECT_TRUE(n.slave->frozen());
  EXPECT_TRUE(n.slave->synced());
  EXPECT_EQ(r.master->counters().global_controls, 1u);
  const std::uint8_t held = r.master->inputs(d)[0];
  r.run_for(10ms);
  EXPECT_EQ(r.master->inputs(d)[0], held) << "frozen inputs";
  // The changed diagnosis came high priority; the master read it and shows
  // Freeze_Mode and Sync_Mode (Station_Status_2 bits 4 and 5).
  EXPECT_EQ(r.master->last_diagnosis(d).status2 & (dp::kDiag2FreezeMode | dp::kDiag2SyncMode),
            dp::kDiag2FreezeMode | dp::kDiag2SyncMode);
  EXPECT_NE(r.master->diagnostics(d).find("Freeze_Mode Sync_Mode"), std::string::npos)
      << r.master->diagnostics(d);
  EXPECT_EQ(r.master->state(d), SlaveState::Online);
  r.master->global_control(dp::kGcUnfreeze | dp::kGcUnsync, 0x01);
  r.run_for(10ms);
  EXPECT_FALSE(n.slave->frozen());
  EXPECT_NE(r.master->inputs(d)[0], held);
  EXPECT_EQ(r.master->last_diagnosis(d).status2 & (dp::kDiag2FreezeMode | dp::kDiag2SyncMode), 0);
}

// Not_Supported (Station_Status_1 bit 4): Freeze and Sync to a slave whose
// Set_Prm did not ask for them. No diagnosis read clears the bit, so the
// master makes the device Fault at once (before: it read the diagnosis
// for 1000 cycles as if the slave were only not ready); after `retry` a
// new Set_Prm clears it and data exchange goes on.
TEST(DpMaster, NotSupportedGlobalControlIsAFaultUntilANewSetPrm) {
  Rig r;
  r.add_slave(pr1721_slave(5));
  auto e = pr1721_entry(5);
  e.prm.station_status &= static_cast<std::uint8_t>(~(dp::kPrmFreezeReq | dp::kPrmSyncReq));
  const std::size_t d = r.master->add(e);
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 100ms));
  r.master->global_control(dp::kGcFreeze, 0x01);
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) != SlaveState::Online; }, 20ms));
  r.run_for(4ms);
  EXPECT_EQ(r.master->state(d), SlaveState::Fault) << r.master->diagnostics(d);
  EXPECT_TRUE(r.master->last_diagnosis(d).status1 & dp::kDiag1NotSupported);
  EXPECT_NE(r.master->diagnostics(d).find("last: Not_Supported"), std::string::npos)
      << r.master->diagnostics(d);
  EXPECT_TRUE(r.master->link(d).last_alarm().appears);
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 150ms))
      << r.master->diagnostics(d);
  EXPECT_EQ(r.master->counters(d).startups, 2u);
  EXPECT_FALSE(r.master->last_diagnosis(d).status1 & dp::kDiag1NotSupported);
}

// Invalid_Slave_Response (Station_Status_1 bit 5, set by the master): a
// Data_Exchange answer of 8 bytes where 16 are configured. The device is
// Fault and its diagnosis, for FBs and the HMI line, carries the bit.
TEST(DpMaster, WrongSizedAnswerIsAnInvalidSlaveResponse) {
  Rig r;
  r.add_slave(pr1721_slave(5));
  auto e = pr1721_entry(5);
  e.input_bytes = 16;  // Chk_Cfg B7 is 8 in, 8 out: the slave answers 8
  const std::size_t d = r.master->add(e);
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Fault; }, 100ms));
  EXPECT_EQ(r.master->counters(d).wrong_size, 1u);
  EXPECT_EQ(r.master->last_diagnosis(d).status1, dp::kDiag1InvalidSlaveResponse);
  const io::DeviceAlarm a = r.master->link(d).last_alarm();
  EXPECT_EQ(a.data >> 24, dp::kDiag1InvalidSlaveResponse);
  EXPECT_TRUE(a.appears);
  EXPECT_NE(r.master->diagnostics(d).find("diag: Invalid_Slave_Response"), std::string::npos)
      << r.master->diagnostics(d);
  EXPECT_NE(r.master->diagnostics(d).find("Data_Exchange answer of 8 bytes, configured 16"),
            std::string::npos);
}

// Ext_Diag_Overflow (Station_Status_3 bit 7): a slave with more extended
// diagnosis than its Max_Diag_Data_Len (the PR1721/31's GSD: 6, no room at
// all) cuts it and sets the bit; the master shows it and goes on with data
// exchange (an overflow is no fault).
TEST(DpMaster, ExtDiagOverflowAtTheGsdsMaxDiagDataLen) {
  Rig r;
  auto c = pr1721_slave(5);
  c.max_diag_len = 6;
  SlaveNode& n = r.add_slave(c);
  const std::size_t d = r.master->add(pr1721_entry(5));
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 100ms));
  n.slave->faults().ext = {0x04, 0x10, 0x20, 0x30};
  r.run_for(10ms);
  const dp::Diagnosis& diag = r.master->last_diagnosis(d);
  EXPECT_EQ(diag.status3, dp::kDiag3ExtDiagOverflow);
  EXPECT_TRUE(diag.status1 & dp::kDiag1ExtDiag);
  EXPECT_TRUE(diag.ext.empty());
  EXPECT_NE(r.master->diagnostics(d).find("Ext_Diag_Overflow"), std::string::npos)
      << r.master->diagnostics(d);
  EXPECT_EQ(r.master->state(d), SlaveState::Online);
  // Room for one block of 4 bytes but not for two: the first is kept.
  c.max_diag_len = 10;
  Rig r2;
  SlaveNode& n2 = r2.add_slave(c);
  const std::size_t d2 = r2.master->add(pr1721_entry(5));
  ASSERT_TRUE(r2.run_until([&] { return r2.master->state(d2) == SlaveState::Online; }, 100ms));
  n2.slave->faults().ext = {0x04, 0x10, 0x20, 0x30, 0x04, 0x40, 0x50, 0x60};
  r2.run_for(10ms);
  EXPECT_EQ(r2.master->last_diagnosis(d2).ext, (std::vector<std::uint8_t>{0x04, 0x10, 0x20, 0x30}));
  EXPECT_EQ(r2.master->last_diagnosis(d2).status3, dp::kDiag3ExtDiagOverflow);
}

// The GAP update: every G (10) rotations one FDL status request to the next
// address of the GAP that is not a slave; a master answering is reported.
TEST(DpMaster, GapUpdateAsksOneAddressEveryGRotations) {
  Rig r;
  r.add_slave(pr1721_slave(2));
  r.master->add(pr1721_entry(2));
  std::vector<std::uint8_t> masters;
  r.master->on_other_master = [&](std::uint8_t a) { masters.push_back(a); };
  r.run_for(100ms);  // 50 rotations: 5 GAP requests (3, 4, 5, 6, 7)
  EXPECT_EQ(r.master->counters().gap_requests, 5u);
  EXPECT_TRUE(masters.empty());
}

// A GAP request to an empty address waits at most 2 ms and is not
// repeated, also with a reply time-out of tens of ms (a PC line): before,
// each one waited 4 x the reply time-out and the slaves' cycles starved.
TEST(DpMaster, GapRequestsDoNotStretchTheCycleOnASlowLine) {
  Rig r;
  r.cfg.min_reply_timeout = 50ms;
  r.cfg.bus.max_retry = 3;
  r.master = std::make_unique<pb::master::DpMaster>(r.cfg, r.master_line.get());
  r.add_slave(pr1721_slave(5));
  const std::size_t d = r.master->add(pr1721_entry(5, 1000));
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 100ms));
  const auto dx = r.master->counters(d).data_exchanges;
  r.run_for(200ms);  // 100 cycles of 2 ms, 10 GAP requests
  EXPECT_GE(r.master->counters().gap_requests, 9u);
  EXPECT_GE(r.master->counters(d).data_exchanges - dx, 85u);
  EXPECT_EQ(r.master->counters(d).retries, 0u);
}

// Deactivated (Station_Status_2 bit 7, the master's own bit): a slave
// configured with active: false is never called; its diagnosis says
// Deactivated (no fault alarm), its device is Offline; the other slave of
// the line exchanges data as usual.
TEST(DpMaster, DeactivatedSlaveIsNeverCalled) {
  Rig r;
  SlaveNode& off = r.add_slave(pr1721_slave(5));
  r.add_slave(pr1721_slave(6));
  auto e = pr1721_entry(5);
  e.active = false;
  const std::size_t d = r.master->add(e);
  const std::size_t d6 = r.master->add(pr1721_entry(6));
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d6) == SlaveState::Online; }, 100ms));
  r.run_for(50ms);
  EXPECT_EQ(off.slave->counters().requests, 0u);
  EXPECT_EQ(r.master->counters(d).startups, 0u);
  EXPECT_EQ(r.master->state(d), SlaveState::Waiting);
  EXPECT_EQ(r.master->link(d).live_state(), io::DeviceState::Offline);
  EXPECT_EQ(r.master->last_diagnosis(d).status2, dp::kDiag2Always1 | dp::kDiag2Deactivated);
  EXPECT_FALSE(r.master->link(d).last_alarm().appears);
  EXPECT_NE(r.master->diagnostics(d).find("diag: Deactivated"), std::string::npos)
      << r.master->diagnostics(d);
  EXPECT_GT(r.master->counters(d6).data_exchanges, 20u);
}

namespace {

// The master's end of the line with a latency the test sets: what the
// slaves send reaches the master `latency` after it was sent, in order (a
// pty or a USB RS-485 adapter whose latency spikes).
class LaggingLine final : public pb::link::Line {
 public:
  LaggingLine(pb::link::Line& inner, const TIME& now) : inner_(inner), now_(now) {}
  TIME latency{0};
  bool send(std::span<const std::uint8_t> t) override { return inner_.send(t); }
  std::size_t receive(std::span<std::uint8_t> buf) override {
    std::array<std::uint8_t, 512> b{};
    for (int i = 0; i < 64; ++i) {
      const std::size_t n = inner_.receive(b);
      if (n == 0) break;
      last_due_ = std::max(now_ + latency, last_due_);
      queue_.push_back({last_due_, std::vector<std::uint8_t>(b.begin(), b.begin() + n)});
    }
    std::size_t out = 0;
    while (!queue_.empty() && queue_.front().first <= now_ &&
           out + queue_.front().second.size() <= buf.size()) {
      const auto& bytes = queue_.front().second;
      std::copy(bytes.begin(), bytes.end(), buf.begin() + out);
      out += bytes.size();
      queue_.erase(queue_.begin());
    }
    return out;
  }
  const pb::link::LineCounters& counters() const override { return inner_.counters(); }
  std::string describe() const override { return "lagging " + inner_.describe(); }

 private:
  pb::link::Line& inner_;
  const TIME& now_;
  TIME last_due_{0};
  std::vector<std::pair<TIME, std::vector<std::uint8_t>>> queue_;
};

}  // namespace

// A latency spike longer than the reply time-out: the master repeats the
// Data_Exchange, and the slave answers both (the repetition with the same
// FCB gets the same answer again). The first answer arrives after the
// repetition was sent and is taken; the master then waits as long again
// before its next request, so the slave's answer to the repetition is
// dropped as late and never taken for the answer to the next request.
// Before, it was: the inputs stayed one exchange stale (the slave's inputs
// change at every tick, so no two answers to two requests are equal), and
// the real answer came in after it.
TEST(DpMaster, LateAnswerToARepeatedRequestIsNotTakenForTheNext) {
  Rig r;
  LaggingLine lag(*r.master_line, r.now);
  r.cfg.min_reply_timeout = 10ms;
  r.cfg.bus.max_retry = 3;
  r.master = std::make_unique<pb::master::DpMaster>(r.cfg, &lag);
  r.add_slave(pr1721_slave(5));
  const std::size_t d = r.master->add(pr1721_entry(5, 1000));
  ASSERT_TRUE(r.run_until([&] { return r.master->state(d) == SlaveState::Online; }, 100ms));
  r.run_for(10ms);
  const auto dx = r.master->counters(d).data_exchanges;
  // Every answer the master takes shows inputs it has not shown before.
  std::uint64_t seen = dx;
  std::uint8_t last = r.master->inputs(d)[0];
  int repeated = 0;
  // Looked at after each tick of the master, which takes at most one
  // answer per tick (Rig::step runs several exchanges in one millisecond).
  auto master_tick = [&] {
    r.master->tick(r.now);
    const auto n = r.master->counters(d).data_exchanges;
    if (n == seen) return;
    repeated += r.master->inputs(d)[0] == last;
    last = r.master->inputs(d)[0];
    seen = n;
  };
  auto watch = [&](int ms) {
    for (int i = 0; i < ms; ++i) {
      r.now += 1ms;
      for (int k = 0; k < 8; ++k) {
        master_tick();
        r.slaves[0]->slave->tick(r.now);
      }
      master_tick();
    }
  };
  lag.latency = 15ms;  // 1.5 reply time-outs, while the request and its repetition go out
  watch(12);
  lag.latency = 0ms;
  watch(40);
  EXPECT_EQ(r.master->counters(d).retries, 1u);
  EXPECT_EQ(repeated, 0) << "an answer to the repetition was taken for a later request";
  EXPECT_EQ(r.master->counters().late_answers, 1u) << "the answer to the repetition";
  EXPECT_EQ(r.master->counters().unexpected, 0u);
  EXPECT_EQ(r.master->state(d), SlaveState::Online);
  EXPECT_GT(r.master->counters(d).data_exchanges - dx, 10u);
}

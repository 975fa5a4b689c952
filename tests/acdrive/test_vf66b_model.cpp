// The simulated VF66B driven with raw assembly bytes (toyo-vf66-devicenet.md):
// assembly selection by J-09/J-10 (§7.2), the Control Supervisor state
// machine (§5.2) and Run1/Run2 event matrix (Table 3.4.3), the speed ramp
// and scaling (§6.1), ST-F (§9.2), faults and fault reset (§5, §7.8),
// fault 18 on communication loss (§12), the restart-after-reset option
// (§13.4 item 21), power-up settings (§9.1), strict params.
#include <gtest/gtest.h>

#include <vector>

#include "plc/io/model_params.hpp"
#include "vf66b/vf66b_model.hpp"

namespace plc::sim {

using namespace std::chrono_literals;
using acdrive::DriveState;

namespace {

Vf66bConfig net_config(unsigned j09 = 1, unsigned j10 = 1) {
  Vf66bConfig c;
  c.j09 = j09;
  c.j10 = j10;
  c.b10 = 3;  // speed reference from the comm option
  c.b11 = 3;  // run command from the comm option
  c.startup_time = 10ms;
  c.accel_time_s = 1;  // 0 -> 1800 rpm in 1 s
  c.decel_time_s = 1;
  c.coast_time_s = 0.5;
  return c;
}

// Raw bytes in, raw bytes out, 1 ms steps.
struct Raw {
  explicit Raw(const Vf66bConfig& c) : m(c) { resize(); }
  void resize() {
    out.assign(m.output_size(), 0);
    in.assign(m.input_size(), 0);
  }
  void step(int n = 1) {
    for (int i = 0; i < n; ++i) {
      now += 1ms;
      m.step(now, 1ms, out, in);
    }
  }
  // Assembly 21 byte 0 bits and speed reference (Table 3.7.1).
  void out21(std::uint8_t bits, std::int16_t ref) {
    out[0] = bits;
    out[1] = 0;
    out[2] = static_cast<std::uint8_t>(ref & 0xFF);
    out[3] = static_cast<std::uint8_t>((ref >> 8) & 0xFF);
  }
  std::int16_t speed71() const { return static_cast<std::int16_t>(in[2] | (in[3] << 8)); }
  Vf66bModel m;
  std::vector<std::uint8_t> out, in;
  TIME now{};
};

constexpr std::uint8_t kFwd = 0x01, kRev = 0x02, kRst = 0x04, kNetCtrl = 0x20, kNetRef = 0x40;

}  // namespace

TEST(Vf66bModel, AssemblySizesFollowJ09J10_Table4_4_Table6_1) {
  const std::vector<std::pair<unsigned, std::size_t>> outs = {{0, 4},  {1, 4},  {2, 8},  {3, 10},
                                                              {4, 12}, {5, 14}, {6, 16}, {7, 18},
                                                              {8, 20}, {9, 22}, {10, 24}};
  for (auto [j09, size] : outs) {
    Vf66bConfig c;
    c.j09 = j09;
    Vf66bModel m(c);
    EXPECT_EQ(m.output_size(), size) << "J-09 = " << j09;
  }
  for (unsigned j10 = 0; j10 <= 15; ++j10) {
    Vf66bConfig c;
    c.j10 = j10;
    Vf66bModel m(c);
    const std::size_t want = j10 <= 1 ? 4 : (j10 == 15 ? 8 : 2 * (j10 + 4));
    EXPECT_EQ(m.input_size(), want) << "J-10 = " << j10;
  }
}

TEST(Vf66bModel, StartupThenReadyWithDriveStateInByte1Of71_Section5_2) {
  Raw r(net_config());
  r.step();
  EXPECT_EQ(r.in[1], 1) << "Startup during the power-up LED test";
  r.step(10);
  EXPECT_EQ(r.m.state(), DriveState::Ready);
  EXPECT_EQ(r.in[1], 3);
  EXPECT_EQ(r.in[0] & 0x10, 0x10) << "Ready bit";
}

TEST(Vf66bModel, RunForwardRampsToReferenceThenStops_Section5_1_Section6_1) {
  Raw r(net_config());
  r.step(20);
  // 900 rpm at SpeedScale 3 = 7200 (§6.1: bus = rpm x 2^3).
  r.out21(kFwd | kNetCtrl | kNetRef, 7200);
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::Enabled);
  EXPECT_EQ(r.in[1], 4);
  EXPECT_TRUE(r.in[0] & 0x04) << "Running1";
  EXPECT_TRUE(r.in[0] & 0x20) << "CtrlFromNet";
  EXPECT_TRUE(r.in[0] & 0x40) << "RefFromNet";
  r.step(250);  // 1800 rpm/s: 0.25 s -> 450 rpm
  EXPECT_NEAR(r.m.speed_rpm(), 450 + 1.8, 1e-6);
  EXPECT_FALSE(r.in[0] & 0x80) << "not yet at reference";
  r.step(300);
  EXPECT_DOUBLE_EQ(r.m.speed_rpm(), 900);
  EXPECT_EQ(r.speed71(), 7200);
  EXPECT_TRUE(r.in[0] & 0x80) << "AtReference";
  // Stop: Run1 = Run2 = 0.
  r.out21(kNetCtrl | kNetRef, 7200);
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::Stopping);
  EXPECT_EQ(r.in[1], 5);
  EXPECT_TRUE(r.in[0] & 0x04) << "Running1 holds while Stopping";
  r.step(600);
  EXPECT_EQ(r.m.state(), DriveState::Ready);
  EXPECT_EQ(r.m.speed_rpm(), 0);
  EXPECT_EQ(r.in[0] & 0x0C, 0);
}

TEST(Vf66bModel, EventMatrixTable3_4_3) {
  // Run1, Run2 before -> after: the trigger event.
  EXPECT_EQ(run_event(false, false, false, false), RunEvent::Stop);  // 0 0
  EXPECT_EQ(run_event(false, false, true, false), RunEvent::Run1);   // 0->1 0
  EXPECT_EQ(run_event(false, false, false, true), RunEvent::Run2);   // 0 0->1
  EXPECT_EQ(run_event(false, false, true, true), RunEvent::None);    // 0->1 0->1
  EXPECT_EQ(run_event(true, true, true, true), RunEvent::None);      // 1 1
  EXPECT_EQ(run_event(true, true, false, true), RunEvent::Run2);     // 1->0 1
  EXPECT_EQ(run_event(true, true, true, false), RunEvent::Run1);     // 1 1->0
  EXPECT_EQ(run_event(true, false, true, false), RunEvent::None) << "held level: no new event";
  EXPECT_EQ(run_event(false, true, false, true), RunEvent::None);
  EXPECT_EQ(run_event(true, false, false, false), RunEvent::Stop);
}

TEST(Vf66bModel, ReverseAndDirectionChangeThroughTheMatrix_Table3_4_3) {
  Raw r(net_config());
  r.step(20);
  r.out21(kRev | kNetCtrl | kNetRef, 4000);  // 500 rpm
  r.step(400);
  EXPECT_EQ(r.m.state(), DriveState::Enabled);
  EXPECT_TRUE(r.m.running2());
  EXPECT_DOUBLE_EQ(r.m.speed_rpm(), -500);
  EXPECT_EQ(r.speed71(), -4000);
  EXPECT_TRUE(r.in[0] & 0x08) << "Running2";
  // Both 1 (0->1 on Run1 while Run2 = 1): no action, still reverse.
  r.out21(kFwd | kRev | kNetCtrl | kNetRef, 4000);
  r.step();
  EXPECT_TRUE(r.m.running2());
  // Run2 1->0 with Run1 = 1: Run1 event, forward.
  r.out21(kFwd | kNetCtrl | kNetRef, 4000);
  r.step();
  EXPECT_TRUE(r.m.running1());
  EXPECT_FALSE(r.m.running2());
  r.step(700);
  EXPECT_DOUBLE_EQ(r.m.speed_rpm(), 500);
}

TEST(Vf66bModel, BothRunBitsRisingTogetherDoNothing_Table3_4_3) {
  Raw r(net_config());
  r.step(20);
  r.out21(kFwd | kRev | kNetCtrl | kNetRef, 4000);
  r.step(50);
  EXPECT_EQ(r.m.state(), DriveState::Ready);
}

TEST(Vf66bModel, NoNetworkControlWithoutB11_3_Section9_2) {
  auto c = net_config();
  c.b11 = 1;  // run command from the terminal block
  Raw r(c);
  r.step(20);
  r.out21(kFwd | kNetCtrl | kNetRef, 4000);
  r.step(50);
  EXPECT_EQ(r.m.state(), DriveState::Ready);
  EXPECT_FALSE(r.in[0] & 0x20) << "CtrlFromNet = 0";
  EXPECT_TRUE(r.in[0] & 0x40) << "RefFromNet = 1 (b-10 = 3)";
}

TEST(Vf66bModel, SpeedReferenceIgnoredUnlessB10_3_Section13_3) {
  auto c = net_config();
  c.b10 = 1;  // analog input 1
  c.local_speed_rpm = 300;
  Raw r(c);
  r.step(20);
  r.out21(kFwd | kNetCtrl | kNetRef, 8000);
  r.step(500);
  EXPECT_FALSE(r.in[0] & 0x40) << "RefFromNet = 0";
  EXPECT_DOUBLE_EQ(r.m.speed_rpm(), 300) << "the bus reference (1000 rpm) is ignored";
}

TEST(Vf66bModel, NetCtrlBitOf21RequestsNetworkControl_Table3_7_1) {
  Raw r(net_config());
  r.step(20);
  r.out21(kFwd | kNetRef, 4000);  // NetCtrl = 0: local control
  r.step(5);
  EXPECT_FALSE(r.in[0] & 0x20);
  EXPECT_EQ(r.m.state(), DriveState::Ready);
}

TEST(Vf66bModel, StfOffIgnoresRunBitsAndStops_Section9_2) {
  Raw r(net_config());
  r.step(20);
  r.m.set_st_f(false);
  r.out21(kFwd | kNetCtrl | kNetRef, 4000);
  r.step(20);
  EXPECT_EQ(r.m.state(), DriveState::Ready) << "run bits have no effect with ST-F off";
  r.m.set_st_f(true);
  r.step(5);
  EXPECT_EQ(r.m.state(), DriveState::Ready) << "a held Run1 is no new event";
  r.out21(kNetCtrl | kNetRef, 4000);
  r.step();
  r.out21(kFwd | kNetCtrl | kNetRef, 4000);
  r.step(100);
  EXPECT_EQ(r.m.state(), DriveState::Enabled);
  r.m.set_st_f(false);
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::Stopping) << "ST-F off while running stops the drive";
}

TEST(Vf66bModel, FaultWhileRunningGoesFaultStopThenFaulted_Section5_2) {
  Raw r(net_config());
  r.step(20);
  r.out21(kFwd | kNetCtrl | kNetRef, 7200);
  r.step(600);
  ASSERT_TRUE(r.m.trip(1));  // overcurrent
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::FaultStop);
  EXPECT_EQ(r.in[1], 6);
  EXPECT_TRUE(r.in[0] & 0x01) << "Faulted";
  EXPECT_TRUE(r.in[0] & 0x04) << "Running1 holds in Fault_Stop";
  r.step(300);  // coast 1800 rpm in 0.5 s: 900 rpm in 0.25 s
  EXPECT_EQ(r.m.state(), DriveState::Faulted);
  EXPECT_EQ(r.in[1], 7);
  EXPECT_FALSE(r.m.trip(3)) << "codes 3 and 4 are blank in Table 6.4";
  EXPECT_FALSE(r.m.trip(33));
}

TEST(Vf66bModel, FaultResetOnRisingEdgeOnly_Section5_2) {
  Raw r(net_config());
  r.step(20);
  r.out21(kRst | kNetCtrl | kNetRef, 0);  // reset bit already high before the fault
  r.step();
  r.m.trip(7);
  r.step(5);
  EXPECT_EQ(r.m.state(), DriveState::Faulted);
  r.step(5);
  EXPECT_EQ(r.m.state(), DriveState::Faulted) << "a held 1 is no reset";
  r.out21(kNetCtrl | kNetRef, 0);
  r.step();
  r.out21(kRst | kNetCtrl | kNetRef, 0);
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::Ready) << "Faulted -> Not_Ready -> Ready";
  EXPECT_FALSE(r.in[0] & 0x01);
}

TEST(Vf66bModel, PersistentCauseSurvivesReset_Section7_8) {
  Raw r(net_config());
  r.step(20);
  r.m.trip(14, true);  // unit overheat, still hot
  r.step();
  r.out21(kRst | kNetCtrl | kNetRef, 0);
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::Faulted);
  r.m.clear_fault_cause();
  r.out21(kNetCtrl | kNetRef, 0);
  r.step();
  r.out21(kRst | kNetCtrl | kNetRef, 0);
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::Ready);
}

TEST(Vf66bModel, Fault18OnConnectionLossUnderNetworkControl_Section12) {
  Raw r(net_config(1, 2));  // 21 out, 120 in (fault field)
  r.step(20);
  r.out21(kFwd | kNetCtrl | kNetRef, 7200);
  r.step(100);
  r.m.io_connection_lost();
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::FaultStop);
  // 120: bytes 2-5 = fault field, bit 17 = code 18 -> byte 4 bit 1 (Table 6.3).
  EXPECT_EQ(r.in[4], 0x02);
  EXPECT_EQ(r.in[2] | r.in[3] | r.in[5], 0);
  EXPECT_TRUE(r.in[1] & 0x04) << "byte 1 bit 2: external DB or communication error";
  r.step(600);
  EXPECT_EQ(r.m.state(), DriveState::Faulted);
  // Communication back: the reset edge (run bits cleared first, §13.2.4).
  r.out21(kNetCtrl | kNetRef, 7200);
  r.step();
  r.out21(kRst | kNetCtrl | kNetRef, 7200);
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::Ready);
  EXPECT_EQ(r.in[4], 0);
}

TEST(Vf66bModel, ConnectionLossWithoutNetworkControlOrIgnoredDoesNotTrip_Section12) {
  auto c = net_config();
  c.b10 = 1;
  c.b11 = 1;
  Raw r(c);
  r.step(20);
  r.m.io_connection_lost();
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::Ready);
  auto c2 = net_config();
  c2.comm_loss_trip = false;
  Raw r2(c2);
  r2.step(20);
  r2.m.io_connection_lost();
  r2.step();
  EXPECT_EQ(r2.m.state(), DriveState::Ready);
}

TEST(Vf66bModel, HeldRunBitNeedsNewEdgeAfterResetByDefault_Section13_4_21) {
  Raw r(net_config());
  r.step(20);
  r.out21(kFwd | kNetCtrl | kNetRef, 4000);
  r.step(10);
  r.m.trip(9);
  r.step(1000);
  ASSERT_EQ(r.m.state(), DriveState::Faulted);
  r.out21(kFwd | kRst | kNetCtrl | kNetRef, 4000);  // reset with Run1 still on
  r.step(10);
  EXPECT_EQ(r.m.state(), DriveState::Ready) << "strict ODVA: no restart without a new edge";
}

TEST(Vf66bModel, RestartAfterResetOptionRestartsWithRunHeld_Section9_2) {
  auto c = net_config();
  c.restart_after_reset = true;
  Raw r(c);
  r.step(20);
  r.out21(kFwd | kNetCtrl | kNetRef, 4000);
  r.step(10);
  r.m.trip(9);
  r.step(1000);
  ASSERT_EQ(r.m.state(), DriveState::Faulted);
  r.out21(kFwd | kRst | kNetCtrl | kNetRef, 4000);
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::Enabled) << "the manual's warning: a reset restarts";
}

TEST(Vf66bModel, SettingsActOnlyAfterPowerCycle_Section9_1) {
  Raw r(net_config(0, 0));
  EXPECT_EQ(r.m.output_size(), 4u);
  r.m.settings().j09 = 2;
  r.m.settings().j10 = 15;
  r.m.settings().j11 = 2;
  EXPECT_EQ(r.m.output_size(), 4u) << "J-09 is read at power-up only";
  EXPECT_EQ(r.m.speed_scale(), 3);
  r.m.power_cycle();
  EXPECT_EQ(r.m.output_size(), 8u);
  EXPECT_EQ(r.m.input_size(), 8u);
  EXPECT_EQ(r.m.output_instance(), 100);
  EXPECT_EQ(r.m.input_instance(), 140);
  EXPECT_EQ(r.m.speed_scale(), 2);
  EXPECT_EQ(r.m.state(), DriveState::Startup);
}

TEST(Vf66bModel, Assembly20RunsForwardOnly_Table3_7_1) {
  Raw r(net_config(0, 0));
  r.step(20);
  r.out[0] = 0x01;  // Run Fwd
  r.out[2] = 0x40;  // 0x1F40 = 8000 = 1000 rpm
  r.out[3] = 0x1F;
  r.step(1000);
  EXPECT_DOUBLE_EQ(r.m.speed_rpm(), 1000);
  // 70: Faulted bit 0, Running1 bit 2, speed actual (Table 3.7.2).
  EXPECT_EQ(r.in[0], 0x04);
  EXPECT_EQ(r.in[1], 0);
  EXPECT_EQ(r.in[2], 0x40);
  EXPECT_EQ(r.in[3], 0x1F);
}

TEST(Vf66bModel, ExtendedModeStartRevFaultReset2AndSpeedReference2_Table6_2) {
  Raw r(net_config(2, 15));  // 100 out, 140 in
  r.step(20);
  // Start (bit 0) + Rev (bit 2); Speed Reference2 = 10000 = half of top.
  r.out = {0x05, 0, 0, 0, 0x10, 0x27, 0, 0};
  r.step(1000);
  EXPECT_DOUBLE_EQ(r.m.speed_rpm(), -900);
  // 140 byte 0: run input (b0), running (b1), reverse command (b3), gate (b7).
  EXPECT_EQ(r.in[0], 0x8B);
  EXPECT_EQ(r.in[1], 0);
  // J-12 = 3: monitors 1, 2, 6 (speed, ARC out, output voltage), LE.
  EXPECT_EQ(static_cast<std::int16_t>(r.in[2] | (r.in[3] << 8)), -10000);
  // External fault 2 (byte 2 bit 4) -> code 30; ProtectErrorCode in b7..b2.
  r.out[2] = 0x10;
  r.step();
  EXPECT_EQ(r.in[1] >> 2, 30);
  r.step(1000);
  EXPECT_EQ(r.m.state(), DriveState::Faulted);
  r.out = {0x20, 0, 0x10, 0, 0, 0, 0, 0};  // Fault Reset2 while Ex-Fail.2 still on
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::Faulted);
  r.out = {0x00, 0, 0, 0, 0, 0, 0, 0};
  r.step();
  r.out = {0x20, 0, 0, 0, 0, 0, 0, 0};
  r.step();
  EXPECT_EQ(r.m.state(), DriveState::Ready);
  EXPECT_EQ(r.in[1] >> 2, 0);
}

TEST(Vf66bModel, LowestCodeWinsInInstance140_Section7_8) {
  Raw r(net_config(1, 15));
  r.step(20);
  r.m.trip(20);
  r.m.trip(7);
  r.step();
  EXPECT_EQ(r.in[1] >> 2, 7);
  EXPECT_EQ(r.m.faults(), (1u << 19) | (1u << 6));
}

TEST(Vf66bModel, WrongLengthOutputIsIgnoredAndCounted_Section13_1_2) {
  Raw r(net_config());
  r.step(20);
  std::vector<std::uint8_t> shortf = {kFwd | kNetCtrl | kNetRef, 0, 0};
  r.m.step(r.now + 1ms, 1ms, shortf, r.in);
  EXPECT_EQ(r.m.bad_frames(), 1u);
  EXPECT_EQ(r.m.state(), DriveState::Ready);
}

TEST(Vf66bModel, ParamsAreStrict) {
  io::ModelParams p;
  p.set("j09", "2");
  p.set("j10", "15");
  p.set("b10", "3");
  p.set("accel_time", "2s");
  Vf66bModel m(p);
  EXPECT_EQ(m.output_size(), 8u);
  EXPECT_EQ(m.input_size(), 8u);
  EXPECT_DOUBLE_EQ(m.active().accel_time_s, 2.0);
  io::ModelParams bad;
  bad.set("j9", "2");
  EXPECT_THROW(Vf66bModel{bad}, io::ParamError);
  io::ModelParams range;
  range.set("j09", "11");
  EXPECT_THROW(Vf66bModel{range}, io::ParamError);
  io::ModelParams scale;
  scale.set("j11", "-127");
  EXPECT_THROW(Vf66bModel{scale}, io::ParamError) << "J-11 keypad range -126..127";
  io::ModelParams code;
  code.set("fault_code", "3");
  EXPECT_THROW(Vf66bModel{code}, io::ParamError);
}

TEST(Vf66bModel, RegisteredAsVf66b) {
  EXPECT_NE(io::DeviceModelRegistry::instance().find("vf66b"), nullptr);
}

TEST(Vf66bModel, FaultSwitchTripsAtConfiguredTime) {
  auto c = net_config();
  c.fault_code = 26;
  c.fault_at = 50ms;
  Raw r(c);
  r.step(49);
  EXPECT_EQ(r.m.faults(), 0u);
  r.step(1);
  EXPECT_EQ(r.m.faults(), 1u << 25);
}

}  // namespace plc::sim

// SinaPos (SINA_POS style) against the simulated E1, telegram 111 and 9.
#include <gtest/gtest.h>

#include "drive_test_util.hpp"
#include "plc/fb/drive/parameter_channel.hpp"
#include "plc/fb/drive/sina_pos.hpp"

namespace plc::drive::test {

struct SinaPosTest : ::testing::Test {
  Bench b;
  SinaPos fb;
  void body() { fb(b.ctx, b.axis); }
  bool until(const std::function<bool()>& p, int n = 10000) {
    return b.run_until([&] { body(); }, p, n);
  }
  void run(int n) {
    b.run([&] { body(); }, n);
  }
  void enable() {
    fb.EnableAxis = true;
    ASSERT_TRUE(until([&] { return fb.AxisEnabled; }, 100));
    EXPECT_EQ(fb.Status, kStatusIdle);
  }
  // With RequireEnableEdgeAfterReset: EnableAxis FALSE for a scan, then TRUE.
  void enable_again() {
    fb.EnableAxis = false;
    run(1);
    fb.EnableAxis = true;
    ASSERT_TRUE(until([&] { return fb.AxisEnabled; }, 100));
  }
  // AckError high for three scans (the drive acts on the STW1.7 edge).
  void ack_error() {
    fb.AckError = true;
    run(3);
    fb.AckError = false;
  }
  void execute(INT mode) {
    fb.ModePos = mode;
    fb.ExecuteMode = false;
    run(1);
    fb.ExecuteMode = true;
    run(1);
  }
};

TEST_F(SinaPosTest, RelativeAndAbsoluteReachTargetWithAxisPosOk) {
  enable();
  fb.Position = 30000;
  fb.Velocity = 6000;  // 6000 x 1000 CU/min = 100000 CU/s
  execute(1);
  EXPECT_EQ(fb.Status, kStatusRunning);
  EXPECT_FALSE(fb.AxisPosOk);
  ASSERT_TRUE(until([&] { return fb.AxisPosOk; }, 3000));
  EXPECT_NEAR(fb.ActPosition, 30000, 10);
  EXPECT_EQ(fb.Status, kStatusIdle);
  fb.Position = -10000;
  execute(2);
  ASSERT_TRUE(until([&] { return fb.AxisPosOk; }, 3000));
  EXPECT_NEAR(fb.ActPosition, -10000, 10);
  fb.Position = 5000;
  execute(1);  // relative again
  ASSERT_TRUE(until([&] { return fb.AxisPosOk; }, 3000));
  EXPECT_NEAR(fb.ActPosition, -5000, 10);
}

TEST_F(SinaPosTest, HandshakeOnTheWire) {
  enable();
  fb.Position = 1000;
  fb.Velocity = 600;
  fb.ModePos = 2;
  fb.ExecuteMode = true;
  body();  // this scan raises STW1.6 with the setpoints
  EXPECT_TRUE(b.axis.STW1 & Stw1Pos::kActivateTask);
  EXPECT_TRUE(b.axis.STW1 & Stw1Pos::kNoRejectTask);
  EXPECT_TRUE(b.axis.STW1 & Stw1Pos::kNoIntermediateStop);
  EXPECT_EQ(b.axis.POS_STW1, PosStw1::kActivateMdi | PosStw1::kAbsolute);
  EXPECT_EQ(b.axis.MDI_TARPOS, 1000);
  EXPECT_EQ(b.axis.MDI_VELOCITY, 600);
  b.ctx.now += b.period;
  ++b.ctx.cycle;
  b.dev->step(b.ctx.now, b.period);
  body();  // the drive acknowledged (ZSW1.12) and dropped target reached
  EXPECT_TRUE(b.axis.ZSW1 & Zsw1Pos::kTaskAck);
  EXPECT_FALSE(b.axis.ZSW1 & Zsw1Pos::kTargetReached);
  EXPECT_TRUE(b.axis.POS_ZSW2 & PosZsw2::kTraversingActive);
  EXPECT_FALSE(b.axis.STW1 & Stw1Pos::kActivateTask);  // dropped after the ack
  ASSERT_TRUE(until([&] { return fb.AxisPosOk; }, 3000));
  EXPECT_FALSE(b.axis.ZSW1 & Zsw1Pos::kTaskAck);  // follows STW1.6 down
}

TEST_F(SinaPosTest, IntermediateStopPausesAndResumes) {
  enable();
  fb.Position = 200000;
  fb.Velocity = 6000;
  execute(2);
  run(300);
  fb.IntermediateStop = false;
  ASSERT_TRUE(until([&] { return b.axis.standstill(); }, 500));
  const auto paused = fb.ActPosition;
  run(50);
  EXPECT_NEAR(fb.ActPosition, paused, 5);
  EXPECT_FALSE(fb.AxisPosOk);
  EXPECT_EQ(fb.Status, kStatusRunning);
  fb.IntermediateStop = true;
  ASSERT_TRUE(until([&] { return fb.AxisPosOk; }, 5000));
  EXPECT_NEAR(fb.ActPosition, 200000, 10);
}

TEST_F(SinaPosTest, CancelTraversingDiscardsTask) {
  enable();
  fb.Position = 500000;
  fb.Velocity = 6000;
  execute(2);
  run(300);
  fb.CancelTraversing = false;
  ASSERT_TRUE(until([&] { return b.axis.standstill(); }, 500));
  fb.CancelTraversing = true;
  run(100);
  EXPECT_LT(fb.ActPosition, 400000);
  EXPECT_FALSE(b.axis.target_reached());
}

TEST_F(SinaPosTest, OverrideScalesVelocity) {
  enable();
  fb.Position = 10000000;
  fb.Velocity = 6000;  // 100000 CU/s
  fb.OverV = 50;
  execute(2);
  run(500);
  EXPECT_NEAR(b.model->velocity(), 50000, 100);
  fb.OverV = 150;  // live in telegram 111
  run(500);
  EXPECT_NEAR(b.model->velocity(), 150000, 300);
}

TEST_F(SinaPosTest, VelocityModeFollowsSetpointAndStops) {
  enable();
  fb.Velocity = 3000;
  fb.Negative = true;
  execute(3);
  run(300);
  EXPECT_NEAR(b.model->velocity(), -50000, 100);
  EXPECT_EQ(fb.Status, kStatusRunning);
  fb.Velocity = 6000;  // re-sent while ExecuteMode stays TRUE
  run(300);
  EXPECT_NEAR(b.model->velocity(), -100000, 200);
  fb.ExecuteMode = false;
  ASSERT_TRUE(until([&] { return b.axis.standstill(); }, 500));
  run(5);
  EXPECT_EQ(fb.Status, kStatusIdle);
  // Both directions at once is refused.
  fb.Positive = true;
  execute(3);
  EXPECT_EQ(fb.Status, kStatusBadSetpoint);
  EXPECT_EQ(fb.DiagID, kErrDirection);
  EXPECT_TRUE(fb.Error);
}

TEST_F(SinaPosTest, JogBothDirectionsAndPt53AReversal) {
  enable();
  fb.ModePos = 7;
  fb.Jog1 = true;
  run(300);
  // Pt533 = 600 rpm = 100000 CU/s with 10000 CU/rev, positive.
  EXPECT_NEAR(b.model->velocity(), 100000, 200);
  EXPECT_TRUE(fb.EPosZSW1 & PosZsw1::kJogActive);
  fb.Jog1 = false;
  ASSERT_TRUE(until([&] { return b.axis.standstill(); }, 500));
  fb.Jog2 = true;
  run(300);
  EXPECT_NEAR(b.model->velocity(), -100000, 200);
  fb.Jog2 = false;
  ASSERT_TRUE(until([&] { return b.axis.standstill(); }, 500));
  // Pt53A = 1 swaps JOG 1 and JOG 2 (only with the pulses off: attribute Setup).
  fb.EnableAxis = false;
  run(50);
  EXPECT_EQ(b.model->set_parameter(pt_pnu(0x53A), 1), 0xFFFF);
  enable();
  fb.Jog1 = true;
  run(300);
  EXPECT_NEAR(b.model->velocity(), -100000, 200);
  fb.Jog1 = false;
  run(100);
}

TEST_F(SinaPosTest, HomingAndSetReferencePoint) {
  sim::HiwinE1Config c;
  c.initial_position = -20000;
  c.home_switch = 0;
  c.home_position = 1000;
  b = Bench(c);
  enable();
  EXPECT_FALSE(fb.AxisRef);
  execute(4);
  EXPECT_EQ(fb.Status, kStatusRunning);
  ASSERT_TRUE(until([&] { return fb.AxisRef && fb.Status == kStatusIdle; }, 20000));
  EXPECT_GT(fb.ActPosition, 1000);  // stopped just past the switch (position 1000)
  EXPECT_LT(fb.ActPosition, 1200);
  // Set reference point: the current position becomes 1000.
  fb.ExecuteMode = false;
  fb.Position = 40000;
  fb.Velocity = 6000;
  execute(1);
  ASSERT_TRUE(until([&] { return fb.AxisPosOk && b.axis.standstill(); }, 3000));
  execute(5);
  ASSERT_TRUE(until([&] { return fb.Status == kStatusIdle; }, 100));
  run(2);
  EXPECT_NEAR(fb.ActPosition, 1000, 2);
  EXPECT_TRUE(fb.AxisRef);
}

TEST_F(SinaPosTest, FaultAndAckError) {
  enable();
  fb.Position = 500000;
  fb.Velocity = 6000;
  execute(2);
  run(100);
  b.model->trip_alarm(0xD00);  // AL.d00
  run(2);
  EXPECT_EQ(fb.Status, kStatusDriveFault);
  EXPECT_EQ(fb.DiagID, 0x0D00);
  EXPECT_EQ(fb.ActFault, 0x0D00);
  EXPECT_TRUE(fb.AxisError);
  EXPECT_FALSE(fb.AxisEnabled);
  ack_error();
  ASSERT_TRUE(until([&] { return fb.AxisEnabled; }, 100));  // EnableAxis held
  EXPECT_EQ(fb.Status, kStatusIdle);
  EXPECT_FALSE(fb.Error);
  execute(2);
  ASSERT_TRUE(until([&] { return fb.AxisPosOk; }, 10000));
}

TEST_F(SinaPosTest, CommunicationErrors) {
  enable();
  b.model->freeze_sign_of_life(true);
  run(8);
  EXPECT_EQ(fb.Status, kStatusComm);
  EXPECT_EQ(fb.DiagID, kErrSignOfLife);
  b.model->freeze_sign_of_life(false);
  b.model->set_answering(false);
  run(2);
  EXPECT_EQ(fb.Status, kStatusComm);
  EXPECT_EQ(fb.DiagID, kErrOffline);
  b.model->set_answering(true);
  ack_error();
  ASSERT_TRUE(until([&] { return fb.AxisEnabled; }, 100));
  EXPECT_FALSE(fb.Error);
}

// EnableAxis is level-controlled, as in the TIA SINA_POS: held through an
// error, it powers the axis again after AckError, never before (PLCopen
// state diagram, softplc-anchors §3.2; ISO 13849-1 §5.2.2: no restart
// without an explicit reset). After a communication loss the drive stays
// off when it answers again; AckError brings it back to operation.
using DrvState = sim::HiwinE1Model::State;
using Path = std::vector<DrvState>;

TEST_F(SinaPosTest, StateDiagram_CommLoss_EnabledAgainAfterAckErrorWithEnableAxisHeld) {
  enable();
  fb.Velocity = 3000;
  fb.Positive = true;
  execute(3);
  run(100);
  b.model->set_answering(false);
  run(10);
  b.model->set_answering(true);
  EXPECT_TRUE(b.stays_off([&] { body(); }, 200));
  EXPECT_TRUE(fb.Error);
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  fb.AckError = true;
  Path path;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100, &path));
  EXPECT_EQ(path, (Path{DrvState::S2, DrvState::S4}));
  EXPECT_TRUE(fb.AxisEnabled);
  EXPECT_FALSE(fb.Lockout);
  EXPECT_EQ(fb.Status, kStatusIdle);
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// A drive fault: AckError acknowledges it (one STW1.7 edge); the drive is
// then switching on inhibited (S1), which the block leaves itself: OFF1
// (S2), then ON and enable operation (S4).
TEST_F(SinaPosTest, StateDiagram_DriveFault_EnabledAgainAfterAckErrorWithEnableAxisHeld) {
  enable();
  b.model->trip_alarm(0xD00);
  run(2);
  EXPECT_TRUE(b.stays_off([&] { body(); }, 200));
  EXPECT_EQ(fb.Status, kStatusDriveFault);
  fb.AckError = true;
  Path path;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100, &path));
  EXPECT_EQ(path, (Path{DrvState::Fault, DrvState::S1, DrvState::S2, DrvState::S4}));
  EXPECT_EQ(b.ack_edges, 1);
  EXPECT_EQ(b.axis.STW1 & Stw1Pos::kFaultAck, 0) << "dropped once the drive acknowledged";
  EXPECT_TRUE(fb.AxisEnabled);
  EXPECT_FALSE(fb.Error);
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// Each AckError edge is one acknowledge: AckError held TRUE from the first
// fault acknowledges neither the next fault (spec §10.2: STW1.7 held at 1
// acknowledges nothing) nor an error whose cause simply went away (the
// communication coming back). A new edge does.
TEST_F(SinaPosTest, StateDiagram_AckErrorHeld_EachFaultNeedsItsOwnAckErrorEdge) {
  enable();
  b.model->trip_alarm(0xD00);
  run(2);
  fb.AckError = true;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100));
  EXPECT_EQ(b.ack_edges, 1);
  b.model->trip_alarm(0x710);  // AckError still TRUE
  run(2);
  EXPECT_TRUE(b.stays_off([&] { body(); }, 200));
  EXPECT_EQ(b.model->state(), DrvState::Fault);
  EXPECT_EQ(b.ack_edges, 1);
  fb.AckError = false;
  run(1);
  fb.AckError = true;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100));
  EXPECT_EQ(b.ack_edges, 2);
  b.model->set_answering(false);  // AckError still TRUE
  run(10);
  b.model->set_answering(true);
  EXPECT_TRUE(b.stays_off([&] { body(); }, 200));
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  EXPECT_EQ(fb.Status, kStatusTaskError);
  fb.AckError = false;
  run(1);
  fb.AckError = true;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100));
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// RequireEnableEdgeAfterReset = TRUE: after AckError the drive stays off
// with Lockout (Status 16#8402, DiagID 16#8006) until EnableAxis is given
// again; after a communication loss and after a drive fault.
TEST_F(SinaPosTest, RequireEnableEdgeAfterReset_LockoutUntilEnableAxisGivenAgain) {
  fb.RequireEnableEdgeAfterReset = true;
  enable();
  b.model->set_answering(false);
  run(10);
  b.model->set_answering(true);
  ack_error();
  EXPECT_TRUE(b.stays_off([&] { body(); }, 200));
  EXPECT_FALSE(fb.AxisEnabled);
  EXPECT_TRUE(fb.Lockout);
  EXPECT_EQ(fb.Status, kStatusLockout);
  EXPECT_EQ(fb.DiagID, kErrRestartInhibit);
  enable_again();
  EXPECT_FALSE(fb.Lockout);
  EXPECT_EQ(fb.Status, kStatusIdle);

  b.model->trip_alarm(0xD00);
  run(2);
  ack_error();
  EXPECT_TRUE(b.stays_off([&] { body(); }, 200));
  EXPECT_FALSE(fb.AxisEnabled);
  EXPECT_EQ(fb.DiagID, kErrRestartInhibit);
  enable_again();
  EXPECT_EQ(b.power_in_error_stop, 0);
}

TEST_F(SinaPosTest, BadModeAndSetpoint) {
  enable();
  execute(6);
  EXPECT_EQ(fb.Status, kStatusBadMode);
  EXPECT_EQ(fb.DiagID, kErrMode);
  fb.Velocity = 0;
  execute(1);
  EXPECT_EQ(fb.Status, kStatusBadSetpoint);
  EXPECT_EQ(fb.DiagID, kErrVelocity);
}

TEST_F(SinaPosTest, Telegram9Positioning) {
  b = Bench(sim::HiwinE1Config{}, 9);
  enable();
  fb.Position = 12345;
  fb.Velocity = 6000;
  execute(2);
  ASSERT_TRUE(until([&] { return fb.AxisPosOk; }, 3000));
  EXPECT_NEAR(fb.ActPosition, 12345, 10);
  EXPECT_TRUE(b.axis.AKTSATZ & Aktsatz::kMdiActive);
  execute(5);  // set reference point needs POS_STW2 (telegram 111)
  EXPECT_EQ(fb.Status, kStatusBadMode);
}

TEST_F(SinaPosTest, OvertravelStopsAndReports) {
  sim::HiwinE1Config c;
  c.pos_limit = 50000;
  b = Bench(c);
  enable();
  fb.Position = 100000;
  fb.Velocity = 3000;
  execute(2);
  ASSERT_TRUE(until([&] { return fb.Error; }, 5000));
  EXPECT_EQ(fb.DiagID, kErrTaskCancelled);
  EXPECT_TRUE(fb.EPosZSW1 & PosZsw1::kPosOvertravel);
  EXPECT_TRUE(fb.AxisWarn);
  EXPECT_EQ(fb.ActWarn, 0x09A0);
  EXPECT_LT(fb.ActPosition, 60000);
  // Moving away from the limit is allowed.
  fb.Position = 0;
  execute(2);
  ASSERT_TRUE(until([&] { return fb.AxisPosOk; }, 5000));
  EXPECT_FALSE(fb.AxisWarn);
}

// Table 3.1.1: OVERRIDE is 0..32767 (0x4000 = 100 %), so SINA_POS's OverV
// range 0..199 %. Outside it OverV is refused (Status 16#8203, DiagID
// 16#8025) and the last valid OVERRIDE stays on the wire; before, 250 % was
// clamped to 199 % without a word.
TEST_F(SinaPosTest, Table3_1_1_OverrideOutside0To199IsRefusedNotClamped) {
  enable();
  fb.Position = 10000000;
  fb.Velocity = 6000;  // 100000 CU/s
  fb.OverV = 50;
  execute(2);
  run(500);
  EXPECT_NEAR(b.model->velocity(), 50000, 100);
  for (INT ov : {250, 200, -5, 32767}) {
    fb.OverV = ov;
    run(200);
    EXPECT_EQ(fb.Status, kStatusBadSetpoint) << ov;
    EXPECT_EQ(fb.DiagID, kErrOverride) << ov;
    EXPECT_TRUE(fb.Error) << ov;
    EXPECT_EQ(io::load_be<std::uint16_t>(b.dev->outputs(), Telegram111Out::kOverride), 0x2000)
        << ov;
    EXPECT_NEAR(b.model->velocity(), 50000, 100) << ov;
  }
  fb.OverV = 199;  // the top of the range is valid
  run(500);
  EXPECT_EQ(fb.Status, kStatusRunning);
  EXPECT_EQ(b.axis.OVERRIDE, 32604);
}

// Table 3.1.1: MDI_ACC/MDI_DEC 0..16384 = 0..100 %; SINA_POS OverAcc/OverDec
// 1..100 %. Outside: the command is refused (16#8203, DiagID 16#8021) and no
// task is sent; before, 150 % went out as 100 % and 0 % as 1 %.
TEST_F(SinaPosTest, Table3_1_1_AccDecOverrideOutside1To100IsRefused) {
  enable();
  fb.Position = 10000;
  fb.Velocity = 6000;
  for (INT bad : {0, 101, 150, -1}) {
    for (bool acc : {true, false}) {
      fb.OverAcc = acc ? bad : 100;
      fb.OverDec = acc ? 100 : bad;
      execute(1);
      EXPECT_EQ(fb.Status, kStatusBadSetpoint) << bad;
      EXPECT_EQ(fb.DiagID, kErrAccel) << bad;
      run(20);
      EXPECT_EQ(b.axis.STW1 & Stw1Pos::kActivateTask, 0) << bad;
      EXPECT_NEAR(b.model->velocity(), 0, 1) << bad;
    }
  }
  fb.OverAcc = 1;
  fb.OverDec = 100;
  execute(1);
  EXPECT_EQ(fb.Status, kStatusRunning);
  EXPECT_EQ(b.axis.MDI_ACC, 164);  // 1 % of 0x4000
}

// Setup / velocity mode (ModePos 3) follows changed setpoints while
// ExecuteMode stays TRUE; a change to an invalid one is refused and shown
// (Status 16#8203), the task runs on at its last valid setpoint, and a valid
// value is followed again. Before, Velocity 0 was ignored without a word.
TEST_F(SinaPosTest, Table3_1_1_VelocityModeChangeToInvalidSetpointIsRefused) {
  enable();
  fb.Velocity = 3000;
  fb.Positive = true;
  execute(3);
  run(300);
  EXPECT_NEAR(b.model->velocity(), 50000, 100);
  fb.Velocity = 0;
  run(100);
  EXPECT_EQ(fb.Status, kStatusBadSetpoint);
  EXPECT_EQ(fb.DiagID, kErrVelocity);
  EXPECT_NEAR(b.model->velocity(), 50000, 100);
  fb.Velocity = 3000;
  fb.OverAcc = 120;
  run(100);
  EXPECT_EQ(fb.DiagID, kErrAccel);
  fb.OverAcc = 100;
  fb.Velocity = 6000;
  run(300);
  EXPECT_EQ(fb.Status, kStatusRunning);
  EXPECT_NEAR(b.model->velocity(), 100000, 200);
}

// MDI_ACC/MDI_DEC scale the Pt534/Pt537 ramps (0x4000 = 100 %, spec §7.6):
// at 100 % the axis reaches 100000 CU/s (20 % of Pt317) in 20 ms, at 50 % in 40 ms.
TEST_F(SinaPosTest, AccelerationOverrideScalesRamp) {
  enable();
  fb.Position = 10000000;
  fb.Velocity = 6000;
  execute(2);
  int t100 = 0;
  ASSERT_TRUE(until([&] { return ++t100, b.model->velocity() > 99000; }, 500));
  fb.CancelTraversing = false;
  ASSERT_TRUE(until([&] { return b.axis.standstill(); }, 500));
  fb.CancelTraversing = true;
  fb.OverAcc = 50;
  execute(2);
  int t50 = 0;
  ASSERT_TRUE(until([&] { return ++t50, b.model->velocity() > 99000; }, 500));
  EXPECT_NEAR(t50 - t100, 20, 3);
  EXPECT_EQ(b.axis.MDI_ACC, 0x2000);
}

// A following error above following_error_limit trips AL.d00 (Table 5.1.1 no. 62).
TEST_F(SinaPosTest, FollowingErrorOverflowTripsD00) {
  sim::HiwinE1Config c;
  c.following_error_limit = 100;  // 100 CU: any real speed exceeds it (v / kv)
  b = Bench(c);
  enable();
  fb.Position = 100000;
  fb.Velocity = 6000;
  execute(2);
  ASSERT_TRUE(until([&] { return fb.Status == kStatusDriveFault; }, 500));
  EXPECT_EQ(fb.ActFault, 0x0D00);
  EXPECT_EQ(b.model->parameter(947), 62);
}

}  // namespace plc::drive::test

// PLCopen blocks against the simulated E1 (telegram 111), in virtual time.
#include <gtest/gtest.h>

#include "drive_test_util.hpp"
#include "plc/fb/drive/mc_blocks.hpp"

namespace plc::drive::test {

struct PlcopenTest : ::testing::Test {
  Bench b;
  MC_Power power;
  MC_Reset reset;
  MC_MoveAbsolute mabs;
  MC_MoveRelative mrel;
  MC_MoveVelocity mvel;
  MC_Home home;
  MC_Stop stop;
  MC_Halt halt;
  MC_ReadStatus rs;
  MC_ReadActualPosition rp;
  void body() {
    power(b.ctx, b.axis);
    reset(b.ctx, b.axis);
    mabs(b.ctx, b.axis);
    mrel(b.ctx, b.axis);
    mvel(b.ctx, b.axis);
    home(b.ctx, b.axis);
    stop(b.ctx, b.axis);
    halt(b.ctx, b.axis);
    rs.Enable = true;
    rs(b.ctx, b.axis);
    rp.Enable = true;
    rp(b.ctx, b.axis);
  }
  bool until(const std::function<bool()>& p, int n = 10000) {
    return b.run_until([&] { body(); }, p, n);
  }
  void run(int n) {
    b.run([&] { body(); }, n);
  }
  void enable() {
    power.Enable = true;
    ASSERT_TRUE(until([&] { return power.Status; }, 100));
    EXPECT_EQ(b.axis.State, AxisState::Standstill);
  }
};

TEST_F(PlcopenTest, PowerWalksS1S2S3S4) {
  // Power-up: S1 until the first telegram; MC_Power(Enable = FALSE, OFF1)
  // sends 0x047E-style OFF1 (ON = 0, no OFF2/OFF3), so the drive goes S2.
  EXPECT_EQ(b.model->state(), sim::HiwinE1Model::State::S1);
  run(2);
  EXPECT_EQ(b.model->state(), sim::HiwinE1Model::State::S2);
  EXPECT_TRUE(rs.Disabled);
  enable();
  EXPECT_TRUE(power.Valid);
  EXPECT_TRUE(rs.Standstill);
  EXPECT_EQ(b.model->state(), sim::HiwinE1Model::State::S4);
}

TEST_F(PlcopenTest, MoveAbsoluteReachesTarget) {
  enable();
  mabs.Position = 100000;
  mabs.Velocity = 200000;
  mabs.Execute = true;
  run(1);
  EXPECT_TRUE(mabs.Busy);
  ASSERT_TRUE(until([&] { return mabs.Done; }, 5000));
  EXPECT_NEAR(rp.Position, 100000, 10);
  EXPECT_EQ(b.axis.State, AxisState::Standstill);
  mabs.Execute = false;
  run(1);
  EXPECT_FALSE(mabs.Done);
}

TEST_F(PlcopenTest, MoveRelativeTwiceAccumulates) {
  enable();
  mrel.Distance = 5000;
  mrel.Velocity = 100000;
  mrel.Execute = true;
  ASSERT_TRUE(until([&] { return mrel.Done; }, 2000));
  mrel.Execute = false;
  run(1);
  mrel.Distance = -2000;
  mrel.Execute = true;
  ASSERT_TRUE(until([&] { return mrel.Done; }, 2000));
  EXPECT_NEAR(b.axis.ActPosition, 3000, 10);
}

TEST_F(PlcopenTest, AbortOneMoveWithAnother) {
  enable();
  mabs.Position = 1000000;
  mabs.Velocity = 100000;
  mabs.Execute = true;
  run(50);
  EXPECT_TRUE(mabs.Busy);
  EXPECT_TRUE(mabs.Active);
  EXPECT_EQ(b.axis.State, AxisState::DiscreteMotion);
  mrel.Distance = -1000;
  mrel.Velocity = 50000;
  mrel.Execute = true;
  run(2);  // mabs is called before mrel in the program: it sees the abort next scan
  EXPECT_TRUE(mabs.CommandAborted);
  EXPECT_FALSE(mabs.Busy);
  EXPECT_TRUE(mrel.Busy);
  const double start = b.axis.ActPosition;
  ASSERT_TRUE(until([&] { return mrel.Done; }, 5000));
  // Relative to the position setpoint when the new task was accepted; the
  // axis braked, so it overshot and came back.
  EXPECT_LT(b.axis.ActPosition, start + 20000);
  EXPECT_TRUE(mabs.CommandAborted);  // held while Execute stays TRUE
  mabs.Execute = false;
  run(1);
  EXPECT_FALSE(mabs.CommandAborted);
}

TEST_F(PlcopenTest, MoveVelocityReachesVelocityThenHalt) {
  enable();
  mvel.Velocity = 50000;
  mvel.Direction = kMcNegativeDirection;
  mvel.Execute = true;
  ASSERT_TRUE(until([&] { return mvel.InVelocity; }, 2000));
  EXPECT_EQ(b.axis.State, AxisState::ContinuousMotion);
  EXPECT_NEAR(b.axis.ActVelocity, -50000, 600);
  EXPECT_TRUE(rs.ContinuousMotion);
  halt.Execute = true;
  run(2);
  EXPECT_TRUE(mvel.CommandAborted);
  EXPECT_FALSE(mvel.InVelocity);
  EXPECT_TRUE(halt.Busy);
  ASSERT_TRUE(until([&] { return halt.Done; }, 2000));
  EXPECT_TRUE(b.axis.standstill());
  run(2);
  EXPECT_EQ(b.axis.State, AxisState::Standstill);
  // The halted task is dropped: a new move works normally.
  mabs.Position = 0;
  mabs.Velocity = 100000;
  mabs.Execute = true;
  ASSERT_TRUE(until([&] { return mabs.Done; }, 5000));
  EXPECT_NEAR(b.axis.ActPosition, 0, 10);
}

TEST_F(PlcopenTest, StopHoldsStoppingWhileExecute) {
  enable();
  mvel.Velocity = 80000;
  mvel.Execute = true;
  run(100);
  stop.Execute = true;
  run(2);
  EXPECT_TRUE(mvel.CommandAborted);
  EXPECT_EQ(b.axis.State, AxisState::Stopping);
  ASSERT_TRUE(until([&] { return stop.Done; }, 2000));
  run(10);
  EXPECT_EQ(b.axis.State, AxisState::Stopping);
  EXPECT_TRUE(rs.Stopping);
  // No motion accepted while Stopping.
  mrel.Distance = 100;
  mrel.Velocity = 1000;
  mrel.Execute = true;
  run(1);
  EXPECT_TRUE(mrel.Error);
  EXPECT_EQ(mrel.ErrorID, kErrStopping);
  mrel.Execute = false;
  stop.Execute = false;
  run(2);
  EXPECT_EQ(b.axis.State, AxisState::Standstill);
  EXPECT_FALSE(stop.Done);
}

TEST_F(PlcopenTest, HomingSetsReference) {
  sim::HiwinE1Config c;
  c.initial_position = 30000;
  c.home_switch = 10000;
  c.home_position = 500;
  b = Bench(c);
  enable();
  EXPECT_FALSE(b.axis.homed());
  home.Execute = true;
  run(1);
  EXPECT_TRUE(home.Busy);
  run(1);
  EXPECT_EQ(b.axis.State, AxisState::Homing);
  EXPECT_TRUE(rs.Homing);
  ASSERT_TRUE(until([&] { return home.Done; }, 20000));
  EXPECT_TRUE(b.axis.homed());
  EXPECT_EQ(b.axis.State, AxisState::Standstill);
  // The position at the switch is 500; the axis stopped a little past it.
  EXPECT_LT(b.axis.ActPosition, 500);
  EXPECT_GT(b.axis.ActPosition, 0);
  // Not from a moving axis.
  home.Execute = false;
  mvel.Velocity = 1000;
  mvel.Execute = true;
  run(5);
  home.Execute = true;
  run(1);
  EXPECT_TRUE(home.Error);
  EXPECT_EQ(home.ErrorID, kErrNotStandstill);
}

TEST_F(PlcopenTest, CommandsRefusedWhenDisabled) {
  run(2);
  mabs.Velocity = 1000;
  mabs.Execute = true;
  run(1);
  EXPECT_TRUE(mabs.Error);
  EXPECT_EQ(mabs.ErrorID, kErrDisabled);
  EXPECT_FALSE(mabs.Busy);
  mabs.Execute = false;
  run(1);
  EXPECT_FALSE(mabs.Error);
  EXPECT_EQ(mabs.ErrorID, 0);
  enable();
  mabs.Velocity = 0;
  mabs.Execute = true;
  run(1);
  EXPECT_EQ(mabs.ErrorID, kErrVelocity);
}

TEST_F(PlcopenTest, EachStopMode) {
  int stop_scans[3] = {};
  for (INT mode : {0, 1, 2}) {
    b = Bench();
    power = MC_Power{};
    mvel = MC_MoveVelocity{};
    enable();
    mvel.Velocity = 200000;
    mvel.Execute = true;
    ASSERT_TRUE(until([&] { return mvel.InVelocity; }, 2000));
    power.StopMode = mode;
    power.Enable = false;
    run(2);  // scan 1 sends the OFF pattern, scan 2 reads the drive's answer
    EXPECT_TRUE(mvel.CommandAborted) << mode;
    EXPECT_EQ(b.axis.State, AxisState::Disabled);
    if (mode == 1) {  // OFF2: S1 at once, coasting (dynamic brake)
      EXPECT_EQ(b.model->state(), sim::HiwinE1Model::State::S1);
      EXPECT_EQ(b.axis.ZSW1 & Zsw1Pos::kNoCoastStop, 0);
    } else if (mode == 2) {  // OFF3: quick stop, ZSW1.5 = 0
      EXPECT_EQ(b.model->state(), sim::HiwinE1Model::State::S5Off3);
      EXPECT_EQ(b.axis.ZSW1 & Zsw1Pos::kNoQuickStop, 0);
    } else {
      EXPECT_EQ(b.model->state(), sim::HiwinE1Model::State::S5Off1);
    }
    int scans = 0;
    until([&] { return ++scans, b.axis.standstill(); }, 5000);
    // OFF3 (Pt538 10 ms) is fastest, then the dynamic brake (50 ms), then
    // OFF1 (Pt537 100 ms); from 1200 rpm = 40 % of Pt317.
    stop_scans[mode] = scans;
    run(5);
    EXPECT_EQ(b.model->state(),
              mode == 0 ? sim::HiwinE1Model::State::S2 : sim::HiwinE1Model::State::S1);
    // And back on.
    power.Enable = true;
    ASSERT_TRUE(until([&] { return power.Status; }, 100)) << mode;
  }
  EXPECT_LT(stop_scans[2], stop_scans[1]);
  EXPECT_LT(stop_scans[1], stop_scans[0]);
  EXPECT_GT(stop_scans[0], 40);  // 40 % of Pt317 on Pt537 = 100 ms: 40 ms ramp
}

TEST_F(PlcopenTest, FaultDuringMoveAndReset) {
  enable();
  mabs.Position = 500000;
  mabs.Velocity = 100000;
  mabs.Execute = true;
  run(100);
  b.model->trip_alarm(0x710, true);
  run(2);
  EXPECT_TRUE(mabs.Error);
  EXPECT_EQ(mabs.ErrorID, kErrDriveFault);
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  EXPECT_EQ(b.axis.FAULT_CODE, 0x0710);
  EXPECT_TRUE(power.Error);
  EXPECT_TRUE(rs.ErrorStop);
  // Motion refused in ErrorStop.
  mrel.Velocity = 1000;
  mrel.Execute = true;
  run(1);
  EXPECT_TRUE(mrel.Error);
  mrel.Execute = false;
  // The cause is still there: MC_Reset times out.
  reset.Timeout = std::chrono::milliseconds(50);
  reset.Execute = true;
  ASSERT_TRUE(until([&] { return reset.Error; }, 100));
  EXPECT_EQ(reset.ErrorID, kErrResetTimeout);
  reset.Execute = false;
  run(1);
  b.model->clear_alarm_cause();
  reset.Execute = true;
  ASSERT_TRUE(until([&] { return reset.Done; }, 100));
  EXPECT_NE(b.axis.State, AxisState::ErrorStop);
  // MC_Power still enabled: S1 -> S2 -> S4 again.
  ASSERT_TRUE(until([&] { return power.Status; }, 100));
  EXPECT_EQ(b.axis.State, AxisState::Standstill);
  EXPECT_FALSE(power.Error);
  mabs.Execute = false;
  run(1);
  mabs.Execute = true;
  ASSERT_TRUE(until([&] { return mabs.Done; }, 10000));
  EXPECT_NEAR(b.axis.ActPosition, 500000, 10);
}

TEST_F(PlcopenTest, SignOfLifeLossErrorsEveryBlock) {
  enable();
  mvel.Velocity = 10000;
  mvel.Execute = true;
  run(20);
  b.model->freeze_sign_of_life(true);
  run(7);  // tolerance 5 scans
  EXPECT_TRUE(b.axis.SignOfLifeLost);
  EXPECT_TRUE(mvel.Error);
  EXPECT_EQ(mvel.ErrorID, kErrSignOfLife);
  EXPECT_EQ(power.ErrorID, kErrSignOfLife);
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  // Outputs go to the safe state: OFF1.
  EXPECT_EQ(b.axis.STW1 & Stw1Pos::kOn, 0);
  b.model->freeze_sign_of_life(false);
  run(2);
  EXPECT_TRUE(power.Error);  // latched until reset
  reset.Execute = true;
  ASSERT_TRUE(until([&] { return reset.Done; }, 100));
  ASSERT_TRUE(until([&] { return power.Status && !power.Error; }, 100));
}

TEST_F(PlcopenTest, StopAnsweringErrorsEveryBlock) {
  enable();
  b.model->set_answering(false);
  run(2);
  EXPECT_EQ(power.ErrorID, kErrOffline);
  EXPECT_TRUE(rp.Error);
  EXPECT_EQ(rp.ErrorID, kErrOffline);
  b.model->set_answering(true);
  run(2);
  EXPECT_FALSE(rp.Error);
  reset.Execute = true;
  ASSERT_TRUE(until([&] { return reset.Done; }, 100));
  ASSERT_TRUE(until([&] { return power.Status; }, 200));
}

TEST_F(PlcopenTest, Telegram9MoveAbsolute) {
  b = Bench(sim::HiwinE1Config{}, 9);
  enable();
  mabs.Position = -20000;
  mabs.Velocity = 100000;
  mabs.Execute = true;
  ASSERT_TRUE(until([&] { return mabs.Done; }, 5000));
  EXPECT_NEAR(b.axis.ActPosition, -20000, 10);
}

}  // namespace plc::drive::test

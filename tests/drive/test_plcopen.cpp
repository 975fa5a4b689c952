// PLCopen blocks against the simulated E1 (telegram 111), in virtual time.
#include <gtest/gtest.h>

#include <limits>

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
  // With RequireEnableEdgeAfterReset: Enable FALSE for a scan, then TRUE.
  void enable_again() {
    power.Enable = false;
    run(1);
    enable();
  }
  // The MDI_TARPOS and STW1 words on the wire (telegram 111, big-endian).
  std::int32_t wire_tarpos() {
    return io::load_be<std::int32_t>(b.dev->outputs(), Telegram111Out::kMdiTarpos);
  }
  std::uint16_t wire_stw1() {
    return io::load_be<std::uint16_t>(b.dev->outputs(), Telegram111Out::kStw1);
  }
  // Execute edge on an Execute block, one scan, Execute stays TRUE.
  template <class Fb>
  void trigger(Fb& fb) {
    fb.Execute = false;
    run(1);
    fb.Execute = true;
    run(1);
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

// Spec Table 3.1.1: MDI_TARPOS is Int32. A target outside it is refused with
// kErrPosition on the Execute edge; nothing goes on the wire (before: 3e9 was
// sent as -1294967296 and the axis moved the wrong way without an error).
TEST_F(PlcopenTest, Table3_1_1_TargetOutsideInt32IsRefusedNotWrapped) {
  enable();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double target : {3e9, 2147483648.0, -2147483649.0, -3e9, nan, inf, -inf}) {
    mabs.Position = target;
    mabs.Velocity = 100000;
    trigger(mabs);
    EXPECT_TRUE(mabs.Error) << target;
    EXPECT_EQ(mabs.ErrorID, kErrPosition) << target;
    EXPECT_FALSE(mabs.Busy) << target;
    mabs.Execute = false;
    mrel.Distance = target;
    mrel.Velocity = 100000;
    trigger(mrel);
    EXPECT_TRUE(mrel.Error) << target;
    EXPECT_EQ(mrel.ErrorID, kErrPosition) << target;
    mrel.Execute = false;
    run(20);
    EXPECT_EQ(wire_tarpos(), 0) << target;
    EXPECT_EQ(wire_stw1() & Stw1Pos::kActivateTask, 0) << target;
    EXPECT_EQ(b.axis.State, AxisState::Standstill) << target;
    EXPECT_NEAR(b.model->velocity(), 0, 1) << target;
  }
  // The edges of the range are valid targets.
  mabs.Position = 2147483647.0;
  trigger(mabs);
  EXPECT_TRUE(mabs.Busy);
  EXPECT_EQ(wire_tarpos(), 2147483647);
  mabs.Execute = false;
  mrel.Distance = -2147483648.0;
  mrel.Velocity = 100000;
  trigger(mrel);
  EXPECT_TRUE(mrel.Busy);
  EXPECT_EQ(wire_tarpos(), std::numeric_limits<std::int32_t>::min());
}

// Spec Table 3.1.1: MDI_VELOCITY is 0..2^31-1 (x 1000 CU/min), MDI_ACC/DEC
// 0..16384 (100 % of Pt534/Pt537, the E1's limit). Out of range, NaN or
// infinite is refused (before: saturated or, for a NaN acceleration, sent as
// the slowest ramp the field holds).
TEST_F(PlcopenTest, Table3_1_1_VelocityAndAccelerationOutsideTheirFieldsAreRefused) {
  enable();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double vmax = 2147483647.0 * 1000.0 / 60.0;  // CU/s
  mabs.Position = 1000;
  for (double v : {inf, nan, vmax * 2, 1e12, -100.0, 0.0, 1.0}) {  // 1 CU/s rounds to 0
    mabs.Velocity = v;
    trigger(mabs);
    EXPECT_EQ(mabs.ErrorID, kErrVelocity) << v;
    mabs.Execute = false;
    mvel.Velocity = v;
    trigger(mvel);
    EXPECT_EQ(mvel.ErrorID, kErrVelocity) << v;
    mvel.Execute = false;
  }
  // 100 % acceleration with the defaults: 3000 rpm x 10000 CU/rev in 100 ms.
  const double a100 = 3000.0 / 60.0 * 10000.0 / 0.1;
  mabs.Velocity = 100000;
  for (double a : {a100 * 1.01, a100 * 10, inf, nan, -1.0, 1e-3}) {
    mabs.Acceleration = a;
    mabs.Deceleration = 0;
    trigger(mabs);
    EXPECT_EQ(mabs.ErrorID, kErrAccel) << a;
    mabs.Execute = false;
    mabs.Acceleration = 0;
    mabs.Deceleration = a;
    trigger(mabs);
    EXPECT_EQ(mabs.ErrorID, kErrAccel) << a;
    mabs.Execute = false;
    mvel.Velocity = 1000;
    mvel.Acceleration = a;
    trigger(mvel);
    EXPECT_EQ(mvel.ErrorID, kErrAccel) << a;
    mvel.Execute = false;
    mvel.Acceleration = 0;
  }
  run(20);
  EXPECT_EQ(wire_stw1() & Stw1Pos::kActivateTask, 0);
  EXPECT_EQ(b.axis.State, AxisState::Standstill);
  // Exactly 100 % goes out as 0x4000, half as 0x2000.
  mabs.Acceleration = a100;
  mabs.Deceleration = a100 / 2;
  trigger(mabs);
  EXPECT_TRUE(mabs.Busy);
  EXPECT_EQ(b.axis.MDI_ACC, 0x4000);
  EXPECT_EQ(b.axis.MDI_DEC, 0x2000);
}

// MC_Home's Position is not sent (the E1 homes to its own parameters), but
// one that no MDI_TARPOS could hold (Table 3.1.1) is refused, not dropped.
TEST_F(PlcopenTest, Table3_1_1_HomePositionOutsideInt32IsRefused) {
  enable();
  for (double p : {std::numeric_limits<double>::quiet_NaN(), 3e9}) {
    home.Position = p;
    trigger(home);
    EXPECT_TRUE(home.Error) << p;
    EXPECT_EQ(home.ErrorID, kErrPosition) << p;
    home.Execute = false;
    run(1);
    EXPECT_EQ(wire_stw1() & Stw1Pos::kStartHoming, 0) << p;
  }
}

// PLCopen MC Part 1 state diagram (softplc-anchors §3.2): an axis error puts
// the axis in ErrorStop, left only through MC_Reset, "which leads to
// Standstill if power is on". MC_Power is level-controlled (as in TIA): with
// Enable held through the error, MC_Reset brings the axis back to
// Standstill by itself. The safety side is kept: no restart without the
// explicit reset (ISO 13849-1 §5.2.2), also when the drive simply answers
// again; no ON and no enable operation in STW1 while in ErrorStop
// (b.power_in_error_stop); a new STW1.7 edge per reset; and the drive's
// switching on inhibited after the acknowledge (spec §5: Fault -> S1) is
// left through OFF1 (S1 -> S2) by the block, before ON (S2 -> S4).
using DrvState = sim::HiwinE1Model::State;
using Path = std::vector<DrvState>;

TEST_F(PlcopenTest, StateDiagram_FaultWhileEnabled_StandstillAfterResetWithEnableHeld) {
  enable();
  b.model->trip_alarm(0x710);  // AL.710, its cause gone at once
  run(2);
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  EXPECT_EQ(power.ErrorID, kErrDriveFault);
  // Never before MC_Reset: the fault stays, and so does ErrorStop.
  EXPECT_TRUE(b.stays_off([&] { body(); }, 300));
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  EXPECT_EQ(b.ack_edges, 0);
  reset.Execute = true;
  Path path;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100, &path));
  EXPECT_TRUE(reset.Done);
  EXPECT_EQ(path, (Path{DrvState::Fault, DrvState::S1, DrvState::S2, DrvState::S4}));
  EXPECT_EQ(b.ack_edges, 1);
  EXPECT_EQ(b.axis.STW1 & Stw1Pos::kFaultAck, 0) << "dropped once the drive acknowledged";
  EXPECT_TRUE(power.Status);
  EXPECT_TRUE(power.Valid);
  EXPECT_FALSE(power.Error) << std::hex << power.ErrorID.value;
  EXPECT_TRUE(rs.Standstill);
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// Enable FALSE when the fault comes, TRUE while the axis is still in
// ErrorStop: nothing happens until MC_Reset, then Standstill.
TEST_F(PlcopenTest, StateDiagram_FaultWhileDisabled_EnableGivenAfterFault_StandstillAfterReset) {
  run(2);
  b.model->trip_alarm(0x710);
  run(2);
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  power.Enable = true;
  EXPECT_TRUE(b.stays_off([&] { body(); }, 300));
  EXPECT_TRUE(power.Error);
  EXPECT_EQ(power.ErrorID, kErrDriveFault);
  reset.Execute = true;
  Path path;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100, &path));
  EXPECT_EQ(path, (Path{DrvState::Fault, DrvState::S1, DrvState::S2, DrvState::S4}));
  EXPECT_FALSE(power.Error) << std::hex << power.ErrorID.value;
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// Every fault needs its own MC_Reset edge and its own STW1.7 edge (spec
// §10.2: a bit held at 1 acknowledges no later fault): with Execute still
// TRUE from the first reset, the second fault stays.
TEST_F(PlcopenTest, StateDiagram_TwoFaultsInARow_EachNeedsItsOwnReset) {
  enable();
  b.model->trip_alarm(0x710);
  run(2);
  reset.Execute = true;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100));
  EXPECT_EQ(b.ack_edges, 1);
  b.model->trip_alarm(0xD00);  // the second fault, Execute still TRUE
  run(2);
  EXPECT_TRUE(b.stays_off([&] { body(); }, 300));
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  EXPECT_EQ(b.model->state(), DrvState::Fault);
  EXPECT_EQ(b.ack_edges, 1);
  reset.Execute = false;
  run(1);
  reset.Execute = true;
  Path path;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100, &path));
  EXPECT_EQ(path, (Path{DrvState::Fault, DrvState::S1, DrvState::S2, DrvState::S4}));
  EXPECT_EQ(b.ack_edges, 2);
  EXPECT_FALSE(power.Error) << std::hex << power.ErrorID.value;
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// Communication lost while moving: ErrorStop, power off (the drive ramps to
// S2); the drive answers again and stays off, with the error latched, until
// MC_Reset; then Standstill with Enable held. The drive had no fault: no
// acknowledge goes out.
TEST_F(PlcopenTest, StateDiagram_CommLoss_StandstillAfterResetWithEnableHeld_NeverBefore) {
  enable();
  mvel.Velocity = 50000;
  mvel.Execute = true;
  ASSERT_TRUE(until([&] { return mvel.InVelocity; }, 2000));
  b.model->set_answering(false);
  run(10);
  EXPECT_EQ(power.ErrorID, kErrOffline);
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  b.model->set_answering(true);
  bool status_with_error = false;
  EXPECT_TRUE(b.stays_off(
      [&] {
        body();
        status_with_error |= power.Status && power.Error;
      },
      300));
  EXPECT_FALSE(status_with_error);
  EXPECT_TRUE(b.axis.CommOk);  // the drive answers again
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  EXPECT_TRUE(power.Error);
  EXPECT_EQ(power.ErrorID, kErrOffline);  // latched until MC_Reset
  EXPECT_TRUE(mvel.Error);
  reset.Execute = true;
  Path path;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100, &path));
  EXPECT_EQ(path, (Path{DrvState::S2, DrvState::S4}));
  EXPECT_EQ(b.ack_edges, 0);
  EXPECT_FALSE(power.Error) << std::hex << power.ErrorID.value;
  EXPECT_TRUE(power.Valid);
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// The PLC's sign-of-life stops (a breakpoint: no block called, STW2 frozen):
// the drive trips AL.FB1 after PNU 925 failures (spec §10.1). When the
// program runs again the axis is in ErrorStop and stays there until
// MC_Reset; then Standstill with Enable held.
TEST_F(PlcopenTest, StateDiagram_PlcSignOfLifeLoss_StandstillAfterResetWithEnableHeld) {
  enable();
  b.run([] {}, 10);
  ASSERT_EQ(b.model->fault_code(), 0xFB1);
  run(2);
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  EXPECT_EQ(power.ErrorID, kErrDriveFault);
  EXPECT_EQ(b.axis.FAULT_CODE, 0xFB1);
  EXPECT_TRUE(b.stays_off([&] { body(); }, 300));
  reset.Execute = true;
  Path path;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100, &path));
  EXPECT_EQ(path, (Path{DrvState::Fault, DrvState::S1, DrvState::S2, DrvState::S4}));
  EXPECT_FALSE(power.Error) << std::hex << power.ErrorID.value;
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// The drive's counter stands still first (16#8002), then the device goes
// offline (a pulled cable seen first as a frozen input image). The
// connection after it is watched afresh (spec §10.1), so CommOk shows the
// drive is back, while the axis stays in ErrorStop, off, until MC_Reset.
TEST_F(PlcopenTest, StateDiagram_SignOfLifeThenOffline_CommOkWhenBack_StandstillAfterReset) {
  enable();
  b.model->freeze_sign_of_life(true);
  run(8);
  EXPECT_EQ(power.ErrorID, kErrSignOfLife);
  b.model->set_answering(false);
  run(5);
  EXPECT_EQ(b.axis.CommError, kErrOffline);
  b.model->freeze_sign_of_life(false);
  b.model->set_answering(true);
  EXPECT_TRUE(b.stays_off([&] { body(); }, 300));
  EXPECT_TRUE(b.axis.CommOk);
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  EXPECT_EQ(power.ErrorID, kErrSignOfLife) << "the first error stays latched";
  reset.Execute = true;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100));
  EXPECT_FALSE(power.Error) << std::hex << power.ErrorID.value;
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// RequireEnableEdgeAfterReset = TRUE (sites that want a new enable command
// after every reset): MC_Reset clears the error, but power stays off with
// 16#8006 until Enable is given again (FALSE for a scan, then TRUE); after
// a communication loss and after a drive fault.
TEST_F(PlcopenTest, RequireEnableEdgeAfterReset_PowerOffWith8006UntilEnableGivenAgain) {
  power.RequireEnableEdgeAfterReset = true;
  enable();
  b.model->set_answering(false);
  run(10);
  b.model->set_answering(true);
  EXPECT_TRUE(b.stays_off([&] { body(); }, 100));
  reset.Execute = true;
  ASSERT_TRUE(until([&] { return reset.Done; }, 100));
  EXPECT_TRUE(b.stays_off([&] { body(); }, 300));
  EXPECT_EQ(b.axis.State, AxisState::Disabled);
  EXPECT_FALSE(power.Status);
  EXPECT_TRUE(power.Error);
  EXPECT_EQ(power.ErrorID, kErrRestartInhibit);
  enable_again();
  EXPECT_FALSE(power.Error);
  EXPECT_TRUE(power.Valid);

  b.model->trip_alarm(0x710);
  run(2);
  EXPECT_EQ(b.axis.State, AxisState::ErrorStop);
  reset.Execute = false;
  run(1);
  reset.Execute = true;
  ASSERT_TRUE(until([&] { return reset.Done; }, 100));
  EXPECT_TRUE(b.stays_off([&] { body(); }, 300));
  EXPECT_EQ(power.ErrorID, kErrRestartInhibit);
  enable_again();
  EXPECT_EQ(b.axis.State, AxisState::Standstill);
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// Enable FALSE before the reset: the reset alone clears everything and the
// next Enable edge powers the drive at once (no extra toggle needed).
TEST_F(PlcopenTest, StateDiagram_EnableDroppedBeforeResetRestartsOnNextEnable) {
  enable();
  b.model->set_answering(false);
  run(5);
  b.model->set_answering(true);
  power.Enable = false;
  run(5);
  reset.Execute = true;
  ASSERT_TRUE(until([&] { return reset.Done; }, 100));
  EXPECT_FALSE(b.axis.RestartInhibit);
  EXPECT_EQ(b.axis.State, AxisState::Disabled);
  enable();
  EXPECT_FALSE(power.Error);
}

// Spec §10.2: STW1.7 is an edge, and the drive must see the 0 before the 1.
// On a bus slower than the scan (one exchange every second scan here; the
// drive's sign-of-life monitoring is off, as the PLC counts per scan), a
// reset started again while the previous acknowledge was still held must
// keep STW1.7 at 0 until the drive has answered once, or the drive sees
// 1, 1 and acknowledges nothing.
TEST_F(PlcopenTest, Spec10_2_EachResetGivesAnAckEdgeTheDriveSeesOnABusSlowerThanTheScan) {
  sim::HiwinE1Config cfg;
  cfg.sign_of_life_monitoring = false;
  b = Bench(cfg);
  auto slow_scan = [&] {
    body();
    b.ctx.now += 1ms;
    ++b.ctx.cycle;
    if (b.ctx.cycle % 2 == 0) b.dev->step(b.ctx.now, 2ms);
  };
  auto slow_until = [&](const std::function<bool()>& pred, int n) {
    for (int i = 0; i < n; ++i) {
      slow_scan();
      if (pred()) return true;
    }
    return false;
  };
  power.Enable = true;
  ASSERT_TRUE(slow_until([&] { return power.Status; }, 100));
  b.model->trip_alarm(0x710, true);  // the cause persists: the first reset holds STW1.7
  reset.Execute = true;
  ASSERT_TRUE(slow_until([&] { return (b.axis.STW1 & Stw1Pos::kFaultAck) != 0; }, 100));
  for (int i = 0; i < 4; ++i) slow_scan();  // the drive has seen the 1 (and refused it)
  b.model->clear_alarm_cause();
  for (int i = 0; i < 4; ++i) slow_scan();
  ASSERT_EQ(b.model->state(), DrvState::Fault) << "the held 1 is no new edge";
  ASSERT_TRUE(reset.Busy);
  // Again: Execute FALSE for a scan, then TRUE in a scan after which the
  // drive does not take a telegram.
  reset.Execute = false;
  slow_scan();
  if (b.ctx.cycle % 2 != 0) slow_scan();
  reset.Execute = true;
  ASSERT_TRUE(slow_until([&] { return reset.Done || reset.Error; }, 200));
  EXPECT_TRUE(reset.Done) << std::hex << reset.ErrorID.value;
  EXPECT_NE(b.model->state(), DrvState::Fault);
  ASSERT_TRUE(slow_until([&] { return power.Status; }, 100));
  EXPECT_FALSE(power.Error) << std::hex << power.ErrorID.value;
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
  // Enable held: S1 -> S2 -> S4, Standstill.
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100));
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
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100));
  EXPECT_FALSE(power.Error);
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
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100));
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

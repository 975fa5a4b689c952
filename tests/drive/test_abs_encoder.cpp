// AbsEncoderInit (spec §7.10) against the simulated E1: success across the
// 3215h reset, refusal by the block (axis enabled), refusal by the drive
// (16), failure (32) and the multi-turn count across a power cycle.
#include <gtest/gtest.h>

#include "drive_test_util.hpp"
#include "plc/fb/drive/abs_encoder_init.hpp"
#include "plc/fb/drive/mc_blocks.hpp"

namespace plc::drive::test {

struct AbsInitTest : ::testing::Test {
  AbsInitTest() {
    sim::HiwinE1Config c;
    c.initial_position = 1234567;  // 123 turns + 4567 CU
    b = Bench(c);
  }
  Bench b;
  AbsEncoderInit fb;
  MC_Power power;
  MC_Reset reset;
  void body() {
    power(b.ctx, b.axis);
    reset(b.ctx, b.axis);
    fb(b.ctx, b.axis);
  }
  bool until(const std::function<bool()>& p, int n = 10000) {
    return b.run_until([&] { body(); }, p, n);
  }
  void run(int n) {
    b.run([&] { body(); }, n);
  }
  void start() {
    fb.Execute = false;
    run(1);
    fb.Execute = true;
  }
};

TEST_F(AbsInitTest, ClearsMultiTurnAndResetsDrive) {
  run(2);
  EXPECT_EQ(b.model->multi_turn(), 123);
  start();
  run(1);
  EXPECT_TRUE(fb.Busy);
  bool saw_running = false;
  ASSERT_TRUE(until([&] {
    saw_running |= fb.Status == 2;
    return fb.Done || fb.Error;
  }));
  EXPECT_TRUE(fb.Done) << std::hex << fb.ErrorID.value;
  EXPECT_TRUE(saw_running);
  EXPECT_EQ(fb.Status, 4);
  EXPECT_EQ(b.model->multi_turn(), 0);
  EXPECT_NEAR(b.axis.ActPosition, 4567, 1);  // single-turn value only
  EXPECT_TRUE(b.axis.CommOk);
  EXPECT_NE(b.axis.State, AxisState::ErrorStop);  // the reset was expected
  // The cleared count survives a power cycle.
  b.model->power_cycle();
  EXPECT_EQ(b.model->multi_turn(), 0);
  // And the axis can be enabled again.
  power.Enable = true;
  ASSERT_TRUE(until([&] { return power.Status; }, 100));
}

TEST_F(AbsInitTest, RefusedWhileEnabled) {
  power.Enable = true;
  ASSERT_TRUE(until([&] { return power.Status; }, 100));
  start();
  run(1);
  EXPECT_TRUE(fb.Error);
  EXPECT_EQ(fb.ErrorID, kErrAbsEnabled);
  EXPECT_EQ(b.model->multi_turn(), 123);
  EXPECT_TRUE(power.Status);  // nothing touched
  // With AllowDisable the block takes power away first, then succeeds.
  fb.AllowDisable = true;
  start();
  ASSERT_TRUE(until([&] { return fb.Done || fb.Error; }));
  EXPECT_TRUE(fb.Done) << std::hex << fb.ErrorID.value;
  EXPECT_EQ(b.model->multi_turn(), 0);
}

// Spec §7.10 step 4: the 3215h reset restarts the drive (the connection
// drops and comes back in S1). With AllowDisable the block took power away
// from an enabled axis; after the reset the axis must not power up by itself
// (PLCopen state diagram: no restart without an explicit reset; the
// multi-turn reference just changed): MC_Power, Enable held, shows 16#8006
// until MC_Reset, and then goes to Standstill without an Enable toggle.
using DrvState = sim::HiwinE1Model::State;
using Path = std::vector<DrvState>;

TEST_F(AbsInitTest, Spec7_10_AfterDriveResetStandstillAfterMcResetWithEnableHeld) {
  power.Enable = true;
  ASSERT_TRUE(until([&] { return power.Status; }, 100));
  fb.AllowDisable = true;
  start();
  ASSERT_TRUE(until([&] { return fb.Done || fb.Error; }));
  ASSERT_TRUE(fb.Done) << std::hex << fb.ErrorID.value;
  EXPECT_TRUE(b.stays_off([&] { body(); }, 300));
  EXPECT_FALSE(power.Status);
  EXPECT_TRUE(power.Error);
  EXPECT_EQ(power.ErrorID, kErrRestartInhibit);
  reset.Execute = true;
  Path path;
  ASSERT_TRUE(b.until_standstill([&] { body(); }, 100, &path));
  // The restarted drive went S1 -> S2 already: OFF1 while power was off.
  EXPECT_EQ(path, (Path{DrvState::S2, DrvState::S4}));
  EXPECT_TRUE(reset.Done);
  EXPECT_FALSE(power.Error) << std::hex << power.ErrorID.value;
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// RequireEnableEdgeAfterReset: the same, but only a new Enable edge powers
// the drive (MC_Reset does not).
TEST_F(AbsInitTest, Spec7_10_RequireEnableEdgeAfterReset_NoRestartUntilEnableGivenAgain) {
  power.RequireEnableEdgeAfterReset = true;
  power.Enable = true;
  ASSERT_TRUE(until([&] { return power.Status; }, 100));
  fb.AllowDisable = true;
  start();
  ASSERT_TRUE(until([&] { return fb.Done || fb.Error; }));
  ASSERT_TRUE(fb.Done) << std::hex << fb.ErrorID.value;
  reset.Execute = true;
  ASSERT_TRUE(until([&] { return reset.Done; }, 100));
  EXPECT_TRUE(b.stays_off([&] { body(); }, 300));
  EXPECT_EQ(power.ErrorID, kErrRestartInhibit);
  power.Enable = false;
  run(1);
  power.Enable = true;
  ASSERT_TRUE(until([&] { return power.Status && !power.Error; }, 100));
}

TEST_F(AbsInitTest, DriveRefuses16) {
  run(2);
  b.model->refuse_next_multiturn_clear();
  start();
  ASSERT_TRUE(until([&] { return fb.Done || fb.Error; }));
  EXPECT_EQ(fb.ErrorID, kErrAbsRefused);
  EXPECT_EQ(fb.Status, 16);
  EXPECT_EQ(b.model->multi_turn(), 123);
}

TEST_F(AbsInitTest, DriveFails32) {
  run(2);
  b.model->fail_next_multiturn_clear();
  start();
  ASSERT_TRUE(until([&] { return fb.Done || fb.Error; }));
  EXPECT_EQ(fb.ErrorID, kErrAbsFailed);
  EXPECT_EQ(fb.Status, 32);
  EXPECT_EQ(b.model->multi_turn(), 123);
}

TEST_F(AbsInitTest, TimeoutWhileRunning) {
  run(2);
  fb.Timeout = std::chrono::milliseconds(100);  // clear takes 500 ms
  start();
  ASSERT_TRUE(until([&] { return fb.Done || fb.Error; }));
  EXPECT_EQ(fb.ErrorID, kErrAbsRunningTimeout);
  EXPECT_EQ(fb.Status, 2);
}

TEST_F(AbsInitTest, DriveNotBackAfterReset) {
  run(2);
  fb.Timeout = std::chrono::milliseconds(800);
  start();
  // Stop answering for good once the reset has been sent.
  ASSERT_TRUE(until([&] { return fb.Step == 5 || fb.Error; }));
  b.model->set_answering(false);
  ASSERT_TRUE(until([&] { return fb.Done || fb.Error; }));
  EXPECT_EQ(fb.ErrorID, kErrAbsResetTimeout);
}

}  // namespace plc::drive::test

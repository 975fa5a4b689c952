// SinaSpeed over telegram 3 against the simulated E1.
#include <gtest/gtest.h>

#include <limits>

#include "drive_test_util.hpp"
#include "plc/fb/drive/scaling.hpp"
#include "plc/fb/drive/sina_speed.hpp"

namespace plc::drive::test {

struct SinaSpeedTest : ::testing::Test {
  Bench b{sim::HiwinE1Config{}, 3};
  SinaSpeed fb;
  void body() { fb(b.ctx, b.axis); }
  bool until(const std::function<bool()>& p, int n = 10000) {
    return b.run_until([&] { body(); }, p, n);
  }
  void run(int n) {
    b.run([&] { body(); }, n);
  }
};

TEST_F(SinaSpeedTest, SpeedSetpointScaledToNsollB) {
  fb.EnableAxis = true;
  ASSERT_TRUE(until([&] { return fb.AxisEnabled; }, 100));
  EXPECT_EQ(fb.Status, kStatusRunning);
  fb.SpeedSp = 1500;  // 50 % of RefSpeed 3000 rpm
  body();
  EXPECT_EQ(b.axis.NSOLL_B, 0x20000000);
  EXPECT_EQ(io::load_be<std::int32_t>(b.dev->outputs(), Telegram3Out::kNsollB), 0x20000000);
  run(5);
  EXPECT_FALSE(fb.SpeedReached);  // ramping (Pt534: 100 ms to 3000 rpm)
  ASSERT_TRUE(until([&] { return fb.SpeedReached; }, 500));
  run(20);
  EXPECT_NEAR(fb.ActVelocity, 1500, 30);
  EXPECT_TRUE(fb.InTolerance);
  // 1500 rpm with 10000 CU/rev = 250000 CU/s; ramp Pt534 100 ms for 3000 rpm.
  EXPECT_NEAR(b.model->velocity(), 250000, 500);
  // G1_XIST1 counts the position.
  const auto x0 = b.axis.G1_XIST1;
  run(100);
  EXPECT_NEAR(static_cast<double>(b.axis.G1_XIST1 - x0), 25000, 300);
  fb.SpeedSp = -3000;
  run(300);
  EXPECT_NEAR(fb.ActVelocity, -3000, 30);
  // OFF3 through ConfigAxis: quick stop (Pt30A = 0: at once), then S1.
  fb.ConfigAxis = 0x1;
  run(30);
  EXPECT_EQ(b.model->state(), sim::HiwinE1Model::State::S1);
  EXPECT_NEAR(b.model->velocity(), 0, 1700);  // below the standstill threshold
  EXPECT_TRUE(fb.Lockout);
  EXPECT_EQ(fb.Status, kStatusLockout);
  fb.ConfigAxis = 0x3;
  ASSERT_TRUE(until([&] { return fb.AxisEnabled; }, 100));
}

TEST_F(SinaSpeedTest, SpeedNear200PercentAndFaultAck) {
  fb.EnableAxis = true;
  fb.SpeedSp = 5999.99F;  // just below +200 %: the top of NSOLL_B
  ASSERT_TRUE(until([&] { return fb.AxisEnabled; }, 100));
  EXPECT_EQ(b.axis.NSOLL_B, *to_nsoll_b(fb.SpeedSp, 3000));
  EXPECT_GT(b.axis.NSOLL_B, 0x7FFF0000);
  run(500);
  EXPECT_NEAR(fb.ActVelocity, 6000, 10);  // ~200 % of 3000 rpm, below Pt316 = 10000
  b.model->trip_alarm(0x510);             // AL.510 overspeed
  run(2);
  EXPECT_EQ(fb.Status, kStatusDriveFault);
  EXPECT_TRUE(fb.Error);
  // Off until AckError; then EnableAxis, held, powers the axis again.
  EXPECT_TRUE(b.stays_off([&] { body(); }, 100));
  fb.AckError = true;
  run(2);
  fb.AckError = false;
  ASSERT_TRUE(until([&] { return fb.AxisEnabled && !fb.Error; }, 100));
  EXPECT_EQ(fb.Status, kStatusRunning);
  EXPECT_EQ(b.ack_edges, 1);
  EXPECT_EQ(b.power_in_error_stop, 0);
}

// Table 3.1.1: NSOLL_B is Int32 with 0x40000000 = 100 %, so |SpeedSp| must
// stay below 200 % of RefSpeed, and RefSpeed must be > 0. An invalid setpoint
// is refused: Status 16#8203, DiagID 16#8026, the last valid NSOLL_B stays on
// the wire (before: 20000 rpm saturated to 0x7FFFFFFF, NaN went out as 0).
TEST_F(SinaSpeedTest, Table3_1_1_SpeedSetpointOutsideNsollBIsRefusedNotSaturated) {
  fb.EnableAxis = true;
  fb.SpeedSp = 1500;
  ASSERT_TRUE(until([&] { return fb.AxisEnabled; }, 100));
  run(300);
  EXPECT_EQ(fb.Status, kStatusRunning);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  struct Bad {
    REAL sp, ref;
  };
  for (const Bad bad : {Bad{20000, 3000}, Bad{6000, 3000}, Bad{-7000, 3000}, Bad{nan, 3000},
                        Bad{inf, 3000}, Bad{1500, 0}, Bad{1500, -3000}, Bad{1500, nan}}) {
    fb.SpeedSp = bad.sp;
    fb.RefSpeed = bad.ref;
    run(100);
    EXPECT_EQ(fb.Status, kStatusBadSetpoint) << bad.sp << " " << bad.ref;
    EXPECT_EQ(fb.DiagID, kErrSpeedSetpoint) << bad.sp << " " << bad.ref;
    EXPECT_TRUE(fb.Error);
    EXPECT_EQ(io::load_be<std::int32_t>(b.dev->outputs(), Telegram3Out::kNsollB), 0x20000000);
    EXPECT_NEAR(b.model->velocity(), 250000, 500);  // still 1500 rpm
  }
  fb.RefSpeed = 3000;
  fb.SpeedSp = -6000;  // exactly -200 % = -2^31 is inside Int32
  run(1);
  EXPECT_EQ(b.axis.NSOLL_B, std::numeric_limits<std::int32_t>::min());
  EXPECT_EQ(fb.Status, kStatusRunning);
}

// SINA_SPEED style, EnableAxis level-controlled: a communication loss leaves
// the drive off when it answers again (PLCopen state diagram; ISO 13849-1
// §5.2.2: no restart without an explicit reset), and AckError brings it back
// with EnableAxis held. With RequireEnableEdgeAfterReset, AckError alone does
// not: Lockout (16#8402, DiagID 16#8006) until EnableAxis is given again.
TEST_F(SinaSpeedTest, StateDiagram_CommLoss_EnabledAgainAfterAckErrorWithEnableAxisHeld) {
  fb.EnableAxis = true;
  fb.SpeedSp = 1500;
  ASSERT_TRUE(until([&] { return fb.AxisEnabled; }, 100));
  b.model->set_answering(false);
  run(10);
  b.model->set_answering(true);
  EXPECT_TRUE(b.stays_off([&] { body(); }, 200));
  EXPECT_TRUE(fb.Error);
  fb.AckError = true;
  ASSERT_TRUE(until([&] { return fb.AxisEnabled && !fb.Error; }, 100));
  fb.AckError = false;
  run(300);
  EXPECT_NEAR(fb.ActVelocity, 1500, 10);
  EXPECT_EQ(b.power_in_error_stop, 0);
}

TEST_F(SinaSpeedTest, RequireEnableEdgeAfterReset_LockoutUntilEnableAxisGivenAgain) {
  fb.RequireEnableEdgeAfterReset = true;
  fb.EnableAxis = true;
  fb.SpeedSp = 1500;
  ASSERT_TRUE(until([&] { return fb.AxisEnabled; }, 100));
  b.model->set_answering(false);
  run(10);
  b.model->set_answering(true);
  EXPECT_TRUE(b.stays_off([&] { body(); }, 200));
  fb.AckError = true;
  run(2);
  fb.AckError = false;
  EXPECT_TRUE(b.stays_off([&] { body(); }, 200));
  EXPECT_FALSE(fb.AxisEnabled);
  EXPECT_TRUE(fb.Lockout);
  EXPECT_EQ(fb.Status, kStatusLockout);
  EXPECT_EQ(fb.DiagID, kErrRestartInhibit);
  fb.EnableAxis = false;
  run(1);
  fb.EnableAxis = true;
  ASSERT_TRUE(until([&] { return fb.AxisEnabled && !fb.Error; }, 100));
}

TEST_F(SinaSpeedTest, WrongTelegram) {
  Bench b111;
  SinaSpeed s;
  s.EnableAxis = true;
  b111.run([&] { s(b111.ctx, b111.axis); }, 2);
  EXPECT_EQ(s.Status, kStatusComm);
  EXPECT_EQ(s.DiagID, kErrTelegram);
}

}  // namespace plc::drive::test

// AcDrive and AcDriveAttribute against the simulated VF66B in virtual time:
// a run/stop/reverse/fault scenario over assemblies 21/71 (§7.3/§7.4), the
// extended assemblies 100/120 and 100/140 (§7.5-§7.7), the fault reset
// sequence of §13.2.4 without automatic restart, SpeedScale on the wire
// (§6.1), device loss (safe outputs), fault 18 (§12) and explicit access
// (§3-§6, §11.1).
#include <gtest/gtest.h>

#include "acdrive_test_util.hpp"
#include "plc/fb/acdrive/ac_drive_attribute.hpp"
#include "plc/fb/acdrive/error_ids.hpp"

namespace plc::acdrive::test {

namespace {
std::int16_t wire_ref(const AcDrive& fb) {
  const auto o = fb.Port.out();
  return static_cast<std::int16_t>(o[2] | (o[3] << 8));
}
bool wire_runs(const AcDrive& fb) { return (fb.Port.out()[0] & 0x03) != 0; }
}  // namespace

TEST(AcDriveFb, RunStopReverseFaultScenario_Section5_Table3_7_1) {
  Bench b;
  b.fb.Enable = true;
  ASSERT_TRUE(b.run_until([&] { return b.fb.State == DriveState::Ready; }, 200));
  EXPECT_TRUE(b.fb.Valid);
  EXPECT_TRUE(b.fb.Ready);
  EXPECT_TRUE(b.fb.CtrlFromNet);
  EXPECT_TRUE(b.fb.RefFromNet);

  // Run forward at 900 rpm.
  b.fb.RunFwd = true;
  b.fb.SpeedRef = 900;
  ASSERT_TRUE(b.run_until([&] { return b.fb.AtReference; }, 2000));
  EXPECT_EQ(b.fb.State, DriveState::Enabled);
  EXPECT_TRUE(b.fb.RunningFwd);
  EXPECT_DOUBLE_EQ(b.fb.ActualSpeed, 900);
  EXPECT_EQ(wire_ref(b.fb), 7200) << "900 rpm x 2^3";

  // Stop.
  b.fb.RunFwd = false;
  b.scan();
  b.scan();
  EXPECT_EQ(b.fb.State, DriveState::Stopping);
  ASSERT_TRUE(b.run_until([&] { return b.fb.State == DriveState::Ready; }, 2000));
  EXPECT_DOUBLE_EQ(b.fb.ActualSpeed, 0);
  EXPECT_FALSE(b.fb.Running);

  // Reverse at 600 rpm.
  b.fb.RunRev = true;
  b.fb.SpeedRef = 600;
  ASSERT_TRUE(b.run_until([&] { return b.fb.AtReference; }, 2000));
  EXPECT_TRUE(b.fb.RunningRev);
  EXPECT_DOUBLE_EQ(b.fb.ActualSpeed, -600);

  // A drive fault: Faulted, ErrorID 8004 (71 has no protect code), run bits
  // dropped by the block.
  b.model->trip(10);  // overspeed
  ASSERT_TRUE(b.run_until([&] { return b.fb.State == DriveState::Faulted; }, 2000));
  EXPECT_TRUE(b.fb.Faulted);
  EXPECT_TRUE(b.fb.Error);
  EXPECT_EQ(b.fb.ErrorID, error_id::kDriveFault);
  EXPECT_FALSE(wire_runs(b.fb));
  EXPECT_TRUE(b.fb.RestartInhibit);

  // Reset while RunRev is still TRUE: the drive resets and does not restart.
  b.fb.FaultReset = true;
  ASSERT_TRUE(b.run_until([&] { return b.fb.State == DriveState::Ready; }, 500));
  EXPECT_FALSE(b.fb.Error);
  b.fb.FaultReset = false;
  for (int i = 0; i < 300; ++i) {
    b.scan();
    ASSERT_FALSE(wire_runs(b.fb)) << "scan " << i << ": no restart without a new command";
    ASSERT_NE(b.model->state(), DriveState::Enabled);
  }
  // Withdraw and give the command again: it runs.
  b.fb.RunRev = false;
  b.scan();
  EXPECT_FALSE(b.fb.RestartInhibit);
  b.fb.RunRev = true;
  ASSERT_TRUE(b.run_until([&] { return b.fb.AtReference; }, 2000));
  EXPECT_DOUBLE_EQ(b.fb.ActualSpeed, -600);
}

TEST(AcDriveFb, FaultResetSendsClearedRunBitsThenAPulse_Section13_2_4) {
  Bench b;
  b.fb.Enable = true;
  b.fb.ResetPulse = 20ms;
  b.run(100);
  b.model->trip(12);
  b.run(5);
  ASSERT_TRUE(b.fb.Faulted);
  b.fb.FaultReset = true;
  b.scan();
  EXPECT_EQ(b.fb.Port.out()[0] & 0x07, 0) << "first scan: run bits and reset 0";
  int high = 0;
  for (int i = 0; i < 100; ++i) {
    b.scan();
    if (b.fb.Port.out()[0] & 0x04) ++high;
  }
  EXPECT_EQ(high, 20) << "held ResetPulse (20 scans of 1 ms), then dropped";
  EXPECT_EQ(b.fb.Port.out()[0] & 0x04, 0);
  EXPECT_FALSE(b.fb.Faulted);
}

TEST(AcDriveFb, SpeedScaleOnTheWire_Section6_1) {
  Bench b;
  b.fb.Enable = true;
  b.fb.SpeedRef = 570.875;
  b.scan();
  EXPECT_EQ(wire_ref(b.fb), 4567) << "the manual's example";
  b.fb.SpeedRef = 5000;  // beyond +-4095.875 at scale 3
  b.scan();
  EXPECT_EQ(b.fb.ErrorID, error_id::kSpeedRange);
  EXPECT_EQ(wire_ref(b.fb), 4567) << "the last valid value stays";
  b.fb.SpeedRef = 100;
  b.scan();
  EXPECT_EQ(b.fb.ErrorID, error_id::kNone);
  EXPECT_EQ(wire_ref(b.fb), 800);
}

TEST(AcDriveFb, SpeedScaleTwoFromJ11) {
  auto cfg = net_config();
  cfg.j11 = 2;
  Bench b(cfg);
  b.fb.Enable = true;
  b.fb.RunFwd = true;
  b.fb.SpeedRef = 1024;
  ASSERT_TRUE(b.run_until([&] { return b.fb.AtReference; }, 2000));
  EXPECT_EQ(wire_ref(b.fb), 4096);
  EXPECT_DOUBLE_EQ(b.fb.ActualSpeed, 1024);
}

TEST(AcDriveFb, DeviceLossReportsOfflineAndWritesSafeOutputs) {
  Bench b;
  b.fb.Enable = true;
  b.fb.RunFwd = true;
  b.fb.SpeedRef = 900;
  ASSERT_TRUE(b.run_until([&] { return b.fb.AtReference; }, 2000));
  b.model->set_answering(false);
  b.scan();  // the device step marks the link Offline
  b.scan();
  EXPECT_EQ(b.fb.ErrorID, error_id::kOffline);
  EXPECT_FALSE(b.fb.Valid);
  EXPECT_FALSE(b.fb.Running);
  EXPECT_FALSE(wire_runs(b.fb));
  EXPECT_EQ(wire_ref(b.fb), 0);
  b.model->set_answering(true);
  b.run(3);
  EXPECT_EQ(b.fb.ErrorID, error_id::kNone);
  EXPECT_TRUE(b.fb.RestartInhibit) << "no restart after the device returns";
  EXPECT_FALSE(wire_runs(b.fb));
}

TEST(AcDriveFb, Fault18OnConnectionLossThenReset_Section12) {
  Bench b(net_config(1, 2));  // 21 -> 120: fault field and protect code
  b.fb.Enable = true;
  // 120 shows no Ready: the run command is given once the drive is up (a
  // level held through its start-up is no event of Table 3.4.3).
  b.run(100);
  b.fb.RunFwd = true;
  b.fb.SpeedRef = 900;
  ASSERT_TRUE(b.run_until([&] { return b.fb.AtReference; }, 2000));
  b.model->io_connection_lost();
  b.run(2);
  EXPECT_TRUE(b.fb.Faulted);
  EXPECT_EQ(b.fb.ProtectCode, 18);
  EXPECT_EQ(b.fb.ErrorID, 0x8412);
  EXPECT_EQ(static_cast<std::uint32_t>(b.fb.FaultBits), 1u << 17);
  EXPECT_STREQ(b.fb.FaultText.c_str(), "Communication timeout error");
  // Fault_Stop -> Faulted once the motor has coasted down; a reset acts in
  // Faulted (§5.2).
  b.fb.RunFwd = false;
  ASSERT_TRUE(b.run_until([&] { return b.model->state() == DriveState::Faulted; }, 2000));
  b.fb.FaultReset = true;
  ASSERT_TRUE(b.run_until([&] { return !b.fb.Faulted && b.fb.ErrorID == 0; }, 2000));
  EXPECT_EQ(b.fb.ProtectCode, 0);
}

TEST(AcDriveFb, ExtendedAssemblies100And140_Table6_2_Table6_3) {
  auto cfg = net_config(2, 15);  // 100 -> 140, J-12 = 3: speed, ARC out, output voltage
  Bench b(cfg);
  b.fb.Enable = true;
  b.fb.RunRev = true;
  b.fb.SpeedRef = 900;  // half of top 1800: Speed Reference2 = 10000
  ASSERT_TRUE(b.run_until([&] { return b.model->speed_rpm() == -900; }, 2000));
  b.scan();
  EXPECT_EQ(b.fb.Port.out()[0], 0x05) << "Start + Rev";
  EXPECT_EQ(b.fb.Port.out()[4] | (b.fb.Port.out()[5] << 8), 10000);
  EXPECT_TRUE(b.fb.RunningRev);
  EXPECT_DOUBLE_EQ(b.fb.ActualSpeed, -900);
  EXPECT_EQ(b.fb.Monitor[0], static_cast<UINT>(static_cast<std::uint16_t>(-10000)));
  // External fault 3 via the model: protect code 31 in byte 1.
  b.model->trip(31);
  b.run(2);
  EXPECT_EQ(b.fb.ProtectCode, 31);
  EXPECT_EQ(b.fb.ErrorID, 0x841F);
  EXPECT_STREQ(b.fb.FaultText.c_str(), "External fault 3");
  b.fb.RunRev = false;
  ASSERT_TRUE(b.run_until([&] { return b.fb.ActualSpeed == 0; }, 2000));
  b.scan();
  b.fb.FaultReset = true;  // Fault Reset2, byte 0 bit 5
  bool saw_reset2 = false;
  ASSERT_TRUE(b.run_until([&] { return !b.fb.Faulted; }, 2000,
                          [&] { saw_reset2 = saw_reset2 || (b.fb.Port.out()[0] & 0x20); }));
  EXPECT_TRUE(saw_reset2);
}

TEST(AcDriveFb, ConfigMismatchIsAnError) {
  Bench b;
  b.fb.OutputInstance = 100;  // the drive has J-09 = 1 (4 bytes)
  b.fb.Enable = true;
  b.scan();
  EXPECT_EQ(b.fb.ErrorID, error_id::kConfig);
  EXPECT_FALSE(b.fb.Valid);
}

TEST(AcDriveFb, UnboundPortIsOffline) {
  AcDrive fb;
  fb.Enable = true;
  fb(ScanContext{});
  EXPECT_EQ(fb.ErrorID, error_id::kOffline);
}

// ---------------------------------------------------------------- explicit
namespace {
struct AttrBench : Bench {
  using Bench::Bench;
  // Runs the attribute block until Done or Error; false if neither came.
  // Done/Error stay visible while Execute is TRUE; the next exec drops it.
  bool exec(AcDriveAttribute& a) {
    a.Execute = false;
    scan([&] { a(ctx, fb); });
    a.Execute = true;
    return run_until([&] { return a.Done || a.Error; }, 50, [&] { a(ctx, fb); });
  }
};
}  // namespace

TEST(AcDriveAttributeFb, GetSpeedScaleAndSpeedActual_Table3_5_2) {
  AttrBench b;
  b.fb.Enable = true;
  b.fb.RunRev = true;
  b.fb.SpeedRef = 100;
  b.run(500);
  AcDriveAttribute a;
  a.Class = 0x2A;
  a.Attribute = 22;
  ASSERT_TRUE(b.exec(a));
  EXPECT_FALSE(a.Error);
  EXPECT_EQ(a.ValueRead, 3);
  a.Attribute = 7;
  ASSERT_TRUE(b.exec(a));
  EXPECT_EQ(a.ValueRead, -800) << "SpeedActual is INT: -100 rpm x 2^3";
  a.Class = 0x0F;  // Parameter 16 Speed Actual
  a.Instance = 16;
  a.Attribute = 1;
  ASSERT_TRUE(b.exec(a));
  EXPECT_EQ(a.ValueRead, -800);
  EXPECT_EQ(a.DataLength, 2);
}

TEST(AcDriveAttributeFb, SetMotorDataAndErrorResponses_Section11_1) {
  AttrBench b;
  b.fb.Enable = true;
  b.run(100);
  AcDriveAttribute a;
  a.Service = 0x10;
  a.Class = 0x28;
  a.Attribute = 6;
  a.Value = 300;  // 30.0 A
  ASSERT_TRUE(b.exec(a));
  EXPECT_FALSE(a.Error);
  a.Service = 0x0E;
  ASSERT_TRUE(b.exec(a));
  EXPECT_EQ(a.ValueRead, 300);
  // FaultCode (0x29 attr 13) is not supported: 0x14.
  a.Class = 0x29;
  a.Attribute = 13;
  ASSERT_TRUE(b.exec(a));
  EXPECT_TRUE(a.Error);
  EXPECT_EQ(a.ErrorID, 0x8514);
  EXPECT_EQ(a.GeneralStatus, 0x14);
  EXPECT_EQ(a.AdditionalCode, 0xFF);
  // Set on a Get attribute: 0x0E.
  a.Service = 0x10;
  a.Attribute = 6;
  a.Value = 3;
  ASSERT_TRUE(b.exec(a));
  EXPECT_EQ(a.ErrorID, 0x850E);
  // A value that does not fit the attribute's type is not sent.
  a.Class = 0x28;
  a.Attribute = 3;
  a.Value = 300;
  ASSERT_TRUE(b.exec(a));
  EXPECT_EQ(a.ErrorID, error_id::kBadInput);
}

// Table 3.4.2 row 12: FaultRst is Set/Get, 0->1 = fault reset. An explicit
// reset through the block works beside AcDrive's own output message (the
// sim plugin's, every scan, with Fault Reset = 0): the edge counts when it
// is written.
TEST(AcDriveAttributeFb, SetFaultRstResetsTheDrive_Table3_4_2) {
  AttrBench b;
  b.fb.Enable = true;
  b.run(100);
  b.model->trip(7);
  ASSERT_TRUE(b.run_until([&] { return b.model->state() == DriveState::Faulted; }, 100));
  AcDriveAttribute a;
  a.Service = 0x10;
  a.Class = 0x29;
  a.Attribute = 12;
  a.Value = 1;
  ASSERT_TRUE(b.exec(a));
  EXPECT_FALSE(a.Error) << "ErrorID " << a.ErrorID;
  ASSERT_TRUE(b.run_until([&] { return !b.fb.Faulted; }, 20));
  EXPECT_EQ(b.model->state(), DriveState::Ready);
}

TEST(AcDriveAttributeFb, DoneHoldsWhileExecuteAndOneScanAfterAnEarlyDrop) {
  AttrBench b;
  b.fb.Enable = true;
  b.run(100);
  AcDriveAttribute a;
  a.Attribute = 22;
  ASSERT_TRUE(b.exec(a));
  for (int i = 0; i < 5; ++i) {
    b.scan([&] { a(b.ctx, b.fb); });
    EXPECT_TRUE(a.Done) << "held while Execute stays TRUE";
  }
  // Execute drops in the scan after the edge, before the answer.
  a.Execute = false;
  b.scan([&] { a(b.ctx, b.fb); });
  a.Execute = true;
  b.scan([&] { a(b.ctx, b.fb); });
  EXPECT_TRUE(a.Busy);
  a.Execute = false;
  b.scan([&] { a(b.ctx, b.fb); });
  EXPECT_TRUE(a.Done) << "the answer shows for one scan";
  b.scan([&] { a(b.ctx, b.fb); });
  EXPECT_FALSE(a.Done);
}

TEST(AcDriveAttributeFb, OfflineDriveRefusesAtOnce) {
  AttrBench b;
  b.model->set_answering(false);
  b.run(2);
  AcDriveAttribute a;
  ASSERT_TRUE(b.exec(a));
  EXPECT_EQ(a.ErrorID, error_id::kOffline);
}

}  // namespace plc::acdrive::test

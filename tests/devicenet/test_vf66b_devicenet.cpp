// The VF66B with its DNET66-Z card over DeviceNet, end to end in lockstep
// virtual time: AcDrive (fblocks/acdrive) on the scanner's buffers, the
// scanner and a slave hosting the VF66B model ("vf66b") on one wire.
// Run / stop / reverse / drive fault and reset (§5, Table 3.4.3), explicit
// access to 0x2A (AcDriveAttribute, §6), fragmented extended input 120
// (§7.6, 12 bytes), and the connection timeout of §12: the master stops
// polling, the slave's I/O connection times out, the drive trips on fault 18
// under network control; the master comes back, allocates again, and a
// fault reset clears it (§13.2 item 5).
#include <gtest/gtest.h>

#include "dn_rig.hpp"
#include "plc/devicenet/objects.hpp"
#include "plc/devicenet/slave_profiles.hpp"
#include "plc/fb/acdrive/ac_drive.hpp"
#include "plc/fb/acdrive/ac_drive_attribute.hpp"
#include "vf66b/vf66b_model.hpp"

using namespace dntest;
namespace ac = plc::acdrive;

namespace {

plc::sim::Vf66bConfig net_config(unsigned j09, unsigned j10) {
  plc::sim::Vf66bConfig c;
  c.j09 = j09;
  c.j10 = j10;
  c.b10 = 3;  // speed reference from the net (§9.2)
  c.b11 = 3;  // run commands from the net
  c.startup_time = 50ms;
  c.accel_time_s = 1;
  c.decel_time_s = 1;
  c.coast_time_s = 0.5;
  return c;
}

struct DriveOnDeviceNet {
  std::shared_ptr<plc::can::MemWire> wire = plc::can::MemWire::create();
  std::unique_ptr<plc::can::Bus> mbus = wire->attach(), sbus = wire->attach();
  dn::Scanner scanner{dn::ScannerConfig{}, mbus.get()};
  std::unique_ptr<dn::Slave> slave;
  plc::sim::Vf66bModel* model = nullptr;
  std::size_t d = 0;
  ac::AcDrive fb;
  plc::ScanContext ctx{};
  bool master_running = true;

  explicit DriveOnDeviceNet(const plc::sim::Vf66bConfig& c) {
    auto cfg = dn::slave_profile("dnet66z");
    cfg->mac = 7;
    cfg->output_assembly = ac::output_instance(c.j09);
    cfg->input_assembly = ac::input_instance(c.j10);
    auto m = std::make_unique<plc::sim::Vf66bModel>(c);
    model = m.get();
    slave = std::make_unique<dn::Slave>(*cfg, std::move(m), *sbus);
    dn::ScanEntry e;
    e.mac = 7;
    e.input_size = ac::input_size(cfg->input_assembly);
    e.output_size = ac::output_size(cfg->output_assembly);
    e.epr = 20ms;
    e.startup.push_back({0x2A, 1, 22, {0x03}});  // SpeedScale 3 (§6.1), a start-up write
    d = scanner.add(e);
    fb.Port.bind(scanner.inputs(d), scanner.outputs(d), &scanner.link(d));
    fb.OutputInstance = cfg->output_assembly;
    fb.InputInstance = cfg->input_assembly;
    fb.SpeedScale = 3;
    fb.TopSpeed = c.top_speed_rpm;
    ctx.period = 1ms;
  }
  void scan(const std::function<void()>& extra = {}) {
    ctx.now += 1ms;
    fb(ctx);
    if (extra) extra();
    if (master_running) scanner.tick(ctx.now);
    slave->tick(ctx.now);
    ++ctx.cycle;
  }
  bool run_until(const std::function<bool()>& pred, int max_scans,
                 const std::function<void()>& extra = {}) {
    for (int i = 0; i < max_scans; ++i) {
      scan(extra);
      if (pred()) return true;
    }
    return false;
  }
};

}  // namespace

TEST(Vf66bDeviceNet, RunStopReverseFaultOverTheScanner_Section5) {
  DriveOnDeviceNet b(net_config(1, 1));  // 21 / 71, 4 bytes each way
  b.fb.Enable = true;
  // Ready, and NetCtrl/NetRef of output 21 taken (one poll later, §13.2 item 3).
  ASSERT_TRUE(b.run_until(
      [&] { return b.fb.State == ac::DriveState::Ready && b.fb.CtrlFromNet && b.fb.RefFromNet; },
      6000))
      << b.scanner.diagnostics(b.d);

  b.fb.RunFwd = true;
  b.fb.SpeedRef = 900;
  ASSERT_TRUE(b.run_until([&] { return b.fb.AtReference; }, 3000));
  EXPECT_TRUE(b.fb.RunningFwd);
  EXPECT_DOUBLE_EQ(b.fb.ActualSpeed, 900);
  EXPECT_EQ(b.model->speed_rpm(), 900);

  b.fb.RunFwd = false;
  ASSERT_TRUE(
      b.run_until([&] { return b.fb.State == ac::DriveState::Ready && !b.fb.Running; }, 3000));
  b.fb.RunRev = true;
  b.fb.SpeedRef = 600;
  ASSERT_TRUE(b.run_until([&] { return b.fb.AtReference; }, 3000));
  EXPECT_TRUE(b.fb.RunningRev);
  EXPECT_DOUBLE_EQ(b.fb.ActualSpeed, -600);

  b.model->trip(10);  // overspeed
  ASSERT_TRUE(b.run_until([&] { return b.fb.Faulted; }, 3000));
  EXPECT_TRUE(b.fb.Error);
  b.fb.RunRev = false;
  ASSERT_TRUE(b.run_until([&] { return b.model->state() == ac::DriveState::Faulted; }, 3000));
  b.fb.FaultReset = true;
  ASSERT_TRUE(b.run_until([&] { return !b.fb.Faulted && !b.fb.Error; }, 3000));
  b.fb.FaultReset = false;
  EXPECT_EQ(b.scanner.counters(b.d).losses, 0u);
  EXPECT_EQ(b.scanner.counters(b.d).wrong_size, 0u);
}

TEST(Vf66bDeviceNet, ExplicitAccessThroughTheScanner_Section6) {
  DriveOnDeviceNet b(net_config(1, 1));
  b.fb.Enable = true;
  ASSERT_TRUE(b.run_until([&] { return b.fb.Valid; }, 6000));
  ac::AcDriveAttribute a;
  a.Service = 0x0E;
  a.Class = 0x2A;
  a.Instance = 1;
  a.Attribute = 22;  // SpeedScale, written 3 at start-up
  a.Execute = true;
  ASSERT_TRUE(b.run_until([&] { return a.Done || a.Error; }, 2000, [&] { a(b.ctx, b.fb); }));
  ASSERT_TRUE(a.Done) << "ErrorID " << a.ErrorID;
  EXPECT_EQ(a.ValueRead, 3);
  a.Execute = false;
  b.scan([&] { a(b.ctx, b.fb); });
  // FaultCode 0x29/13 is "Not Support" (§13.2 item 7): Error Response 0x14.
  a.Class = 0x29;
  a.Attribute = 13;
  a.Execute = true;
  ASSERT_TRUE(b.run_until([&] { return a.Done || a.Error; }, 2000, [&] { a(b.ctx, b.fb); }));
  ASSERT_TRUE(a.Error);
  EXPECT_EQ(a.GeneralStatus, 0x14);
}

TEST(Vf66bDeviceNet, Fault18OnConnectionTimeoutThenReallocationAndReset_Section12) {
  DriveOnDeviceNet b(net_config(1, 2));  // 21 -> 120: 12 input bytes, fragmented
  b.fb.Enable = true;
  ASSERT_TRUE(b.run_until([&] { return b.fb.Valid; }, 6000)) << b.scanner.diagnostics(b.d);
  b.run_until([] { return false; }, 100);
  b.fb.RunFwd = true;
  b.fb.SpeedRef = 900;
  ASSERT_TRUE(b.run_until([&] { return b.fb.AtReference; }, 3000));
  // The master stops (a breakpoint in a PLC without a bus thread, a cable
  // pulled at the master): no polls for 4 x EPR = 80 ms -> Timed Out.
  b.master_running = false;
  ASSERT_TRUE(b.run_until([&] { return b.slave->poll_state() == dn::kConnTimedOut; }, 200));
  EXPECT_EQ(b.model->state(), ac::DriveState::FaultStop);
  b.master_running = true;
  // The master notices, the FB reports the loss, then re-allocation.
  ASSERT_TRUE(b.run_until([&] { return !b.fb.Port.online(); }, 200));
  ASSERT_TRUE(b.run_until([&] { return b.fb.Error; }, 2));
  b.fb.RunFwd = false;
  ASSERT_TRUE(b.run_until([&] { return b.fb.Port.online() && b.fb.Faulted; }, 5000))
      << b.scanner.diagnostics(b.d);
  EXPECT_EQ(b.fb.ProtectCode, 18);
  EXPECT_STREQ(b.fb.FaultText.c_str(), "Communication timeout error");
  EXPECT_EQ(b.scanner.counters(b.d).allocations, 2u);
  ASSERT_TRUE(b.run_until([&] { return b.model->state() == ac::DriveState::Faulted; }, 3000));
  b.fb.FaultReset = true;
  ASSERT_TRUE(b.run_until([&] { return !b.fb.Faulted && b.fb.ProtectCode == 0; }, 3000));
  b.fb.FaultReset = false;
  // The block lets run bits through once its reset pulse is over and the
  // run inputs were seen FALSE (AcDrive's restart inhibit, §13.2 item 4).
  ASSERT_TRUE(b.run_until([&] { return !b.fb.RestartInhibit; }, 3000));
  b.fb.RunFwd = true;
  ASSERT_TRUE(b.run_until([&] { return b.fb.AtReference; }, 3000))
      << "state " << int(b.fb.State) << " model " << int(b.model->state()) << " err "
      << b.fb.ErrorID << " inhibit " << b.fb.RestartInhibit << " running " << b.fb.Running
      << " speed " << b.fb.ActualSpeed << " ready " << b.fb.Ready;
}

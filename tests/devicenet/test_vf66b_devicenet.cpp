// The VF66B with its DNET66-Z card over DeviceNet, end to end in lockstep
// virtual time: AcDrive (fblocks/acdrive) on the scanner's buffers, the
// scanner and a slave hosting the VF66B model ("vf66b") on one wire.
// Run / stop / reverse / drive fault and reset (§5, Table 3.4.3), explicit
// access to 0x2A (AcDriveAttribute, §6), fragmented extended input 120
// (§7.6, 12 bytes), and the connection timeout of §12: the master stops
// polling, the slave's I/O connection times out, the drive trips on fault 18
// under network control; the master comes back, allocates again, and a
// fault reset clears it (§13.2 item 5). Explicit Sets of the data the
// output assembly also carries, against polls frame by frame (Tables 3.4.2,
// 3.5.2, 3.7.1).
#include <gtest/gtest.h>

#include <algorithm>
#include <initializer_list>
#include <vector>

#include "dn_rig.hpp"
#include "plc/devicenet/identifiers.hpp"
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

// ---------------------------------------------------------------------------
// Explicit Set against polled I/O, frame by frame: a master of the test's own
// on the wire (§1.4 [std] layouts, 8/8 body format, unfragmented), so that a
// test decides when a poll command and an explicit request reach the DNET66-Z.
// The reading (vf66b_model.hpp): a datum both write holds the last value
// written; a poll overwrites an explicit Set, which stands until then.
namespace {

struct FrameMaster {
  static constexpr std::uint8_t kMaster = 0, kDrive = 7;
  std::shared_ptr<plc::can::MemWire> wire = plc::can::MemWire::create();
  std::unique_ptr<plc::can::Bus> mbus = wire->attach(), sbus = wire->attach();
  std::unique_ptr<dn::Slave> slave;
  plc::sim::Vf66bModel* model = nullptr;
  plc::TIME now{};
  std::vector<std::uint8_t> answer;  // the last explicit response: service, data

  explicit FrameMaster(const plc::sim::Vf66bConfig& c) {
    auto cfg = dn::slave_profile("dnet66z");
    cfg->mac = kDrive;
    cfg->dup_mac_wait = 1ms;
    cfg->output_assembly = ac::output_instance(c.j09);
    cfg->input_assembly = ac::input_instance(c.j10);
    auto m = std::make_unique<plc::sim::Vf66bModel>(c);
    model = m.get();
    slave = std::make_unique<dn::Slave>(*cfg, std::move(m), *sbus);
    for (int i = 0; i < 10 && !slave->online(); ++i) tick();
  }
  void tick(int n = 1) {
    for (int i = 0; i < n; ++i) {
      now += 1ms;
      slave->tick(now);
      plc::can::Frame f;
      while (mbus->receive(f))
        if (f.std_id() == dn::group2_id(kDrive, dn::kG2ExplicitResponse) && f.len >= 2)
          answer.assign(f.data.begin() + 1, f.data.begin() + f.len);
    }
  }
  void send(std::uint8_t msg_id, std::initializer_list<std::uint8_t> data) {
    plc::can::Frame f;
    f.id = dn::group2_id(kDrive, msg_id);
    f.len = static_cast<std::uint8_t>(data.size());
    std::copy(data.begin(), data.end(), f.data.begin());
    mbus->send(f);
  }
  // Explicit request frames (header = the master's MAC, then the message).
  void allocate(std::uint8_t choice) {
    send(dn::kG2Unconnected, {kMaster, 0x4B, dn::kClassDeviceNet, 1, choice, kMaster});
  }
  void set(std::uint8_t cls, std::uint8_t attr, std::initializer_list<std::uint8_t> v) {
    std::vector<std::uint8_t> d = {kMaster, 0x10, cls, 1, attr};
    d.insert(d.end(), v);
    plc::can::Frame f;
    f.id = dn::group2_id(kDrive, dn::kG2ExplicitRequest);
    f.len = static_cast<std::uint8_t>(d.size());
    std::copy(d.begin(), d.end(), f.data.begin());
    mbus->send(f);
  }
  void poll(std::initializer_list<std::uint8_t> out) { send(dn::kG2Poll, out); }
  // Sends one request, ticks once, and tells whether it succeeded.
  bool set_now(std::uint8_t cls, std::uint8_t attr, std::initializer_list<std::uint8_t> v) {
    answer.clear();
    set(cls, attr, v);
    tick();
    return !answer.empty() && answer[0] == (0x10 | dn::kResponseBit);
  }
};

}  // namespace

// Table 3.4.2 rows 3 and 12, Table 3.5.2 row 8 (Set/Get, supported): a
// master with only the explicit connection runs the drive with Run1 and
// SpeedRef and resets a fault with FaultRst. No poll overwrites them.
TEST(Vf66bDeviceNet, ExplicitRun1SpeedRefFaultRstWithoutIo_Table3_4_2_Table3_5_2) {
  FrameMaster m(net_config(1, 1));
  ASSERT_TRUE(m.slave->online());
  m.allocate(dn::kAllocExplicit);
  m.tick(60);  // allocated; the drive's start-up (50 ms) is over
  ASSERT_EQ(m.slave->allocation(), dn::kAllocExplicit);
  ASSERT_EQ(m.model->state(), ac::DriveState::Ready);
  ASSERT_TRUE(m.set_now(0x2A, 8, {0x20, 0x1C})) << "SpeedRef 7200 = 900 r/min";
  ASSERT_TRUE(m.set_now(0x29, 3, {1})) << "Run1";
  m.tick(600);
  EXPECT_EQ(m.model->state(), ac::DriveState::Enabled);
  EXPECT_DOUBLE_EQ(m.model->speed_rpm(), 900);
  ASSERT_TRUE(m.set_now(0x29, 3, {0}));
  m.model->trip(5);
  m.tick(600);
  ASSERT_EQ(m.model->state(), ac::DriveState::Faulted);
  ASSERT_TRUE(m.set_now(0x29, 12, {1})) << "FaultRst 0->1";
  m.tick();
  EXPECT_EQ(m.model->state(), ac::DriveState::Ready);
}

// Which wins with polled I/O (Table 3.5.2 row 8, Table 3.7.1): the last
// write, in the order the frames arrive, also within one tick of the slave.
TEST(Vf66bDeviceNet, LastWriteWinsBetweenPollAndExplicitSet_Table3_5_2_Table3_7_1) {
  FrameMaster m(net_config(1, 1));
  m.allocate(dn::kAllocExplicit | dn::kAllocPoll);
  m.tick(60);
  // Establish the poll connection: EPR (class 5, instance 2, attr 9) = 0,
  // no timeout.
  m.send(dn::kG2ExplicitRequest,
         {FrameMaster::kMaster, 0x10, dn::kClassConnection, dn::kConnPoll, dn::kConnAttrEpr, 0, 0});
  m.tick();
  ASSERT_EQ(m.slave->poll_state(), dn::kConnEstablished);
  // Poll: Run1, NetCtrl, NetRef, 4000 = 500 r/min.
  m.poll({0x61, 0, 0xA0, 0x0F});
  m.tick(400);
  ASSERT_DOUBLE_EQ(m.model->speed_rpm(), 500);
  ASSERT_TRUE(m.set_now(0x2A, 8, {0x40, 0x1F})) << "SpeedRef 8000 = 1000 r/min";
  m.tick(400);
  EXPECT_DOUBLE_EQ(m.model->speed_rpm(), 1000) << "the Set stands until the next poll";
  m.poll({0x61, 0, 0xA0, 0x0F});
  m.tick(400);
  EXPECT_DOUBLE_EQ(m.model->speed_rpm(), 500) << "the poll overwrote it";
  // Poll, then Set, in the same tick: the Set came last.
  m.poll({0x61, 0, 0xA0, 0x0F});
  m.set(0x2A, 8, {0x40, 0x1F});
  m.tick(400);
  EXPECT_DOUBLE_EQ(m.model->speed_rpm(), 1000);
  // Set, then poll, in the same tick: the poll came last.
  m.set(0x2A, 8, {0x40, 0x1F});
  m.poll({0x61, 0, 0xA0, 0x0F});
  m.tick(400);
  EXPECT_DOUBLE_EQ(m.model->speed_rpm(), 500);
}

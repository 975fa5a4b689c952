// The drive and safety scenarios of tests/drive and tests/safety, run over
// PROFINET: the same FBs and the same device models, but the FBs' ports are
// bound to the controller's staging buffers and the models sit behind
// PnDevice, every byte crossing the in-memory Ethernet hub as RT_CLASS_1
// frames and every record as RPC Write/Read (lockstep virtual time).
//   E1: MDI positioning (test_sina_pos RelativeAndAbsolute...), parameter
//       access (test_sina_para), absolute-encoder init with the 3215h reset
//       (test_abs_encoder ClearsMultiTurnAndResetsDrive), two faults each
//       reset with MC_Reset while Enable is held (test_plcopen
//       StateDiagram_TwoFaultsInARow...).
//   NORD: F-parameters at start-up and automatic reintegration
//       (test_startup), an acknowledgeable device fault (test_fault_matrix
//       DeviceFault_Acknowledgeable), and the device lost on the bus: the
//       F-host passivates, outputs safe, reintegration only after
//       acknowledgement.
#include <gtest/gtest.h>

#include "hiwin_e1/hiwin_e1_model.hpp"
#include "plc/fb/drive/abs_encoder_init.hpp"
#include "plc/fb/drive/diag_codes.hpp"
#include "plc/fb/drive/mc_blocks.hpp"
#include "plc/fb/drive/sina_para.hpp"
#include "plc/fb/drive/sina_pos.hpp"
#include "plc/fb/safety/f_host_diag.hpp"
#include "plc/fb/safety/nord_error_codes.hpp"
#include "plc/fb/safety/nord_safe_io.hpp"
#include "plc/sim/nord_profisafe_model.hpp"
#include "pn_loop.hpp"

namespace {

using namespace pntest;
namespace io = plc::io;
namespace drive = plc::drive;

ControllerConfig quick_retry(std::uint16_t data_hold_factor = 3) {
  ControllerConfig c;
  c.retry = std::chrono::milliseconds(50);
  c.data_hold_factor = data_hold_factor;
  return c;
}

// ---- E1 over PROFINET ----------------------------------------------------------

struct E1OverPn {
  explicit E1OverPn(plc::sim::HiwinE1Config cfg = {}, std::uint16_t data_hold_factor = 3)
      : loop(quick_retry(data_hold_factor)) {
    io::ModelParams p;
    p.set("telegram", "111");
    auto m = std::make_unique<plc::sim::HiwinE1Model>(cfg);
    model = m.get();
    loop.add("hiwin_e1", p, std::move(m));
    axis.Telegram = 111;
    loop.bind(axis.Port, 0);
    online = loop.run_until([&] { return loop.online(0); }, 1000);
    loop.step();  // first frame from the drive
  }
  void scan(const std::function<void()>& body) {
    body();
    ctx.now += 1ms;
    ++ctx.cycle;
    loop.step();
  }
  bool until(const std::function<void()>& body, const std::function<bool()>& pred, int n) {
    for (int i = 0; i < n; ++i) {
      scan(body);
      if (pred()) return true;
    }
    return false;
  }
  void run(const std::function<void()>& body, int n) {
    for (int i = 0; i < n; ++i) scan(body);
  }
  PnLoop loop;
  plc::sim::HiwinE1Model* model = nullptr;
  drive::DriveAxis axis;
  plc::ScanContext ctx{plc::TIME{}, 1ms, 0};
  bool online = false;
};

// tests/drive/test_sina_pos.cpp RelativeAndAbsoluteReachTargetWithAxisPosOk.
TEST(PnScenarios, E1_MdiPositioningRelativeAndAbsoluteOverProfinet) {
  E1OverPn b;
  ASSERT_TRUE(b.online);
  drive::SinaPos fb;
  auto body = [&] { fb(b.ctx, b.axis); };
  fb.EnableAxis = true;
  ASSERT_TRUE(b.until(
      body, [&] { return fb.AxisEnabled; }, 100));
  auto execute = [&](plc::INT mode) {
    fb.ModePos = mode;
    fb.ExecuteMode = false;
    b.run(body, 1);
    fb.ExecuteMode = true;
    b.run(body, 1);
  };
  fb.Position = 30000;
  fb.Velocity = 6000;
  execute(1);
  EXPECT_EQ(fb.Status, drive::kStatusRunning);
  ASSERT_TRUE(b.until(
      body, [&] { return fb.AxisPosOk; }, 3000));
  EXPECT_NEAR(fb.ActPosition, 30000, 10);
  fb.Position = -10000;
  execute(2);
  ASSERT_TRUE(b.until(
      body, [&] { return fb.AxisPosOk; }, 3000));
  EXPECT_NEAR(fb.ActPosition, -10000, 10);
  EXPECT_EQ(b.loop.ctrl->counters(0).bad_total(), 0u);
}

// tests/drive/test_sina_para.cpp ReadWriteValuesAndArrays (hiwin §6.4).
TEST(PnScenarios, E1_ParameterAccessOverProfinet) {
  E1OverPn b;
  ASSERT_TRUE(b.online);
  drive::SinaPara fb;
  auto body = [&] { fb(b.ctx, b.axis); };
  auto job = [&] {
    fb.Start = false;
    b.run(body, 1);
    fb.Start = true;
    const bool ok = b.until(
        body, [&] { return fb.Done || fb.Error; }, 200);
    fb.Start = false;
    return ok;
  };
  fb.ReadWrite = false;
  fb.Pnu = drive::pt_pnu(0x317);
  ASSERT_TRUE(job());
  ASSERT_TRUE(fb.Done) << fb.ErrorID.value;
  EXPECT_EQ(fb.ValueRead, 3000);
  fb.ReadWrite = true;
  fb.Pnu = drive::pt_pnu(0x534);
  fb.Format = 0x06;
  fb.Value = 250;
  ASSERT_TRUE(job());
  ASSERT_TRUE(fb.Done) << fb.ErrorID.value;
  fb.ReadWrite = false;
  ASSERT_TRUE(job());
  EXPECT_EQ(fb.ValueRead, 250);
  fb.Pnu = 964;
  fb.Count = 7;
  ASSERT_TRUE(job());
  ASSERT_TRUE(fb.Done);
  EXPECT_EQ(fb.ValuesRead[0], 0xAAA) << "PNU 964.0 manufacturer (hiwin §6.1)";
}

// tests/drive/test_abs_encoder.cpp ClearsMultiTurnAndResetsDrive (hiwin
// §7.10): 3200h, then the 3215h reset, during which the drive stops
// answering; over PROFINET that is an AR lost and connected again.
TEST(PnScenarios, E1_AbsoluteEncoderInitAcrossTheResetOverProfinet) {
  plc::sim::HiwinE1Config c;
  c.initial_position = 1234567;
  E1OverPn b(c);
  ASSERT_TRUE(b.online);
  drive::AbsEncoderInit fb;
  drive::MC_Power power;
  drive::MC_Reset reset;
  auto body = [&] {
    power(b.ctx, b.axis);
    reset(b.ctx, b.axis);
    fb(b.ctx, b.axis);
  };
  b.run(body, 2);
  EXPECT_EQ(b.model->multi_turn(), 123);
  fb.Execute = false;
  b.run(body, 1);
  fb.Execute = true;
  ASSERT_TRUE(b.until(
      body, [&] { return fb.Done || fb.Error; }, 20000));
  EXPECT_TRUE(fb.Done) << std::hex << fb.ErrorID.value << " step " << std::dec << fb.Step << "; "
                       << b.loop.ctrl->diagnostics(0) << "; device "
                       << b.loop.devices[0].dev->describe();
  EXPECT_EQ(b.model->multi_turn(), 0);
  ASSERT_TRUE(b.until(
      body, [&] { return b.axis.CommOk; }, 5000));
  EXPECT_NEAR(b.axis.ActPosition, 4567, 1);
  power.Enable = true;
  ASSERT_TRUE(b.until(
      body, [&] { return power.Status; }, 200));
}

// tests/drive/test_plcopen.cpp StateDiagram_TwoFaultsInARow_EachNeedsItsOwnReset
// (PLCopen state diagram; hiwin §5 Fault -> S1, §10.2 STW1.7 edge): over
// PROFINET each MC_Reset acknowledges its fault with its own STW1.7 edge and
// MC_Power, Enable held, walks the drive S1 -> S2 -> S4 back to Standstill.
TEST(PnScenarios, E1_FaultThenMcResetWithEnableHeldBackToStandstillOverProfinet) {
  E1OverPn b;
  ASSERT_TRUE(b.online);
  drive::MC_Power power;
  drive::MC_Reset reset;
  auto body = [&] {
    power(b.ctx, b.axis);
    reset(b.ctx, b.axis);
  };
  power.Enable = true;
  ASSERT_TRUE(b.until(
      body, [&] { return power.Status; }, 200));
  for (const std::uint16_t alarm : {0x710, 0xD00}) {
    b.model->trip_alarm(alarm);
    ASSERT_TRUE(b.until(
        body, [&] { return b.axis.State == drive::AxisState::ErrorStop; }, 50));
    b.run(body, 100);
    EXPECT_EQ(b.model->state(), plc::sim::HiwinE1Model::State::Fault) << "not before MC_Reset";
    EXPECT_EQ(b.axis.STW1 & (drive::Stw1Pos::kOn | drive::Stw1Pos::kEnableOperation), 0);
    reset.Execute = false;
    b.run(body, 1);
    reset.Execute = true;
    ASSERT_TRUE(b.until(
        body, [&] { return b.axis.State == drive::AxisState::Standstill && power.Status; }, 200))
        << std::hex << alarm << " " << power.ErrorID.value;
    EXPECT_TRUE(reset.Done);
    EXPECT_FALSE(power.Error);
  }
  EXPECT_EQ(b.loop.ctrl->counters(0).bad_total(), 0u);
}

// tests/drive/test_plcopen.cpp StateDiagram_CommLoss... over PROFINET, the
// cable pulled: with a data-hold time longer than the axis' sign-of-life
// tolerance (32 ms here, as in cell_profinet.yaml, against 5 scans) the
// axis sees the drive's counter stand still (16#8002) before the controller
// declares the device lost (16#8001). When the link returns the controller
// connects again and the counter of the new connection is watched afresh
// (hiwin §10.1: from its first non-zero value): CommOk is TRUE again, while
// the axis stays in ErrorStop, without power, until MC_Reset; then Enable,
// held all along, brings it back to Standstill.
TEST(PnScenarios, E1_DeviceLostOnTheBusOffUntilMcResetThenStandstillWithEnableHeld) {
  E1OverPn b(plc::sim::HiwinE1Config{}, 32);
  ASSERT_TRUE(b.online);
  drive::MC_Power power;
  drive::MC_Reset reset;
  auto body = [&] {
    power(b.ctx, b.axis);
    reset(b.ctx, b.axis);
  };
  power.Enable = true;
  ASSERT_TRUE(b.until(
      body, [&] { return power.Status; }, 200));
  const Mac dev_mac = b.loop.devices[0].eth->mac();
  const Ipv4 dev_ip = b.loop.devices[0].dev->ip();
  b.loop.hub.set_link_up(dev_mac, false);
  b.loop.net.set_link_up(dev_ip, false);
  ASSERT_TRUE(b.until(
      body, [&] { return power.ErrorID == drive::kErrSignOfLife; }, 20));
  ASSERT_TRUE(b.until(
      body, [&] { return b.axis.CommError == drive::kErrOffline; }, 100));
  EXPECT_EQ(power.ErrorID, drive::kErrOffline);
  b.loop.hub.set_link_up(dev_mac, true);
  b.loop.net.set_link_up(dev_ip, true);
  const auto power_bits = drive::Stw1Pos::kOn | drive::Stw1Pos::kEnableOperation;
  bool power_asked = false;
  ASSERT_TRUE(b.until(
      body,
      [&] {
        power_asked |= (b.axis.STW1 & power_bits) != 0;
        return b.axis.CommOk;
      },
      5000))
      << b.loop.ctrl->diagnostics(0);
  b.run(
      [&] {
        body();
        power_asked |= (b.axis.STW1 & power_bits) != 0;
      },
      300);
  EXPECT_FALSE(power_asked) << "no power before MC_Reset";
  EXPECT_TRUE(b.axis.CommOk);
  EXPECT_EQ(b.axis.State, drive::AxisState::ErrorStop);
  EXPECT_NE(b.model->state(), plc::sim::HiwinE1Model::State::S4);
  reset.Execute = true;
  ASSERT_TRUE(b.until(
      body, [&] { return b.axis.State == drive::AxisState::Standstill && power.Status; }, 200))
      << std::hex << power.ErrorID.value;
  EXPECT_TRUE(reset.Done);
  EXPECT_FALSE(power.Error);
}

// ---- NORD PROFIsafe over PROFINET ------------------------------------------------

struct NordOverPn {
  NordOverPn() : loop(quick_retry()) {
    io::ModelParams p;
    const std::pair<const char*, const char*> kv[] = {
        {"dip_address", "1"}, {"p840", "305441741"}, {"p802_1", "1"},
        {"p802_2", "1"},      {"p802_3", "1"},       {"p802_4", "1"},
        {"p802_5", "1"},      {"p802_6", "1"},       {"p802_7", "1"}};
    for (auto [k, v] : kv) p.set(k, v);
    auto m = std::make_unique<plc::sim::NordProfisafeModel>(p);
    model = m.get();
    loop.add("nord_profisafe", {}, std::move(m));
    loop.bind(io.FMOD.port, 0);
    io.FMOD.F_Dest_Add = 1;
    io.FMOD.F_Source_Add = 10;
    io.FMOD.F_WD_Time = 100;
    io.FMOD.F_iPar_CRC = 0x1234ABCD;
    online = loop.run_until([&] { return loop.online(0); }, 1000);
  }
  void scan(int n = 1) {
    for (int i = 0; i < n; ++i) {
      ctx.now += 1ms;
      io(ctx);
      loop.step();
      ++ctx.cycle;
    }
  }
  template <class P>
  int scan_until(P pred, int max) {
    for (int i = 1; i <= max; ++i) {
      scan();
      if (pred()) return i;
    }
    return -1;
  }
  bool running() const { return io.FMOD.STATE == plc::safety::FHostState::Run && !io.QBAD; }
  bool all_safe() const {
    for (auto b : io.FMOD.IN_DATA)
      if (b != 0) return false;
    return io.QBAD && !model->ossd(0) && !model->ossd(1) && !model->ossd(2);
  }
  void ack() {
    io.FMOD.ACK_REI = true;
    scan();
    io.FMOD.ACK_REI = false;
    scan();
  }
  // Safe while waiting, reintegrates only after a rising ACK_REI.
  void expect_ack_reintegration() {
    ASSERT_GT(scan_until([&] { return io.ACK_REQ; }, 3000), 0) << "ACK_REQ never raised";
    for (int i = 0; i < 300; ++i) {
      scan();
      ASSERT_TRUE(all_safe()) << "not safe while waiting for ACK, scan " << i;
    }
    ack();
    ASSERT_GT(scan_until([&] { return running(); }, 20), 0);
    scan(2);
    EXPECT_EQ(model->ossd(0), io.OSSD1);
  }
  PnLoop loop;
  plc::sim::NordProfisafeModel* model = nullptr;
  plc::safety::NORD_SAFE_IO io;
  plc::ScanContext ctx{};
  bool online = false;
};

// tests/safety/test_startup.cpp ParametersThenAutomaticReintegration_Spec8_2:
// the F-parameter record (nord §2.2) goes by RPC Write.
TEST(PnScenarios, Nord_8_2_FParametersByRecordThenAutomaticReintegration) {
  NordOverPn r;
  ASSERT_TRUE(r.online);
  EXPECT_TRUE(r.io.QBAD);
  r.io.OSSD1 = true;
  ASSERT_GT(r.scan_until([&] { return r.running(); }, 100), 0);
  EXPECT_TRUE(r.model->fparams_ok());
  EXPECT_FALSE(r.io.ACK_REQ);
  EXPECT_EQ(r.io.DIAG, 0);
  r.scan(5);
  EXPECT_TRUE(r.model->ossd(0)) << "SO1 on through PROFINET";
  EXPECT_GE(r.loop.ctrl->counters(0).records_ok, 1u);
}

// tests/safety/test_fault_matrix.cpp DeviceFault_Acknowledgeable_Spec8_4_7.
TEST(PnScenarios, Nord_8_4_7_DeviceFaultPassivatesUntilAcknowledged) {
  NordOverPn r;
  ASSERT_TRUE(r.online);
  r.io.OSSD1 = true;
  ASSERT_GT(r.scan_until([&] { return r.running(); }, 100), 0);
  r.model->inject_device_fault(plc::safety::nord::err::kEncoder);
  ASSERT_GT(r.scan_until([&] { return r.io.QBAD; }, 101), 0);
  r.scan(5);
  EXPECT_TRUE(r.io.DIAG & plc::safety::diag::kDevFault);
  EXPECT_TRUE(r.all_safe());
  r.model->clear_device_fault();
  r.expect_ack_reintegration();
}

// The device lost on the bus (a pulled cable): the controller declares it
// lost within the data-hold time, its inputs read zero, the F-host
// passivates within F_WD_Time; the device, without controller frames, drops
// its AR and its outputs go to the substitute state (SO1 off); when the
// link returns the controller reconnects, the F-parameters are written
// again, and the F-host reintegrates only after acknowledgement.
TEST(PnScenarios, Nord_DeviceLostOnTheBusPassivatesAndNeedsAcknowledgeAfterReturn) {
  NordOverPn r;
  ASSERT_TRUE(r.online);
  r.io.OSSD1 = true;
  ASSERT_GT(r.scan_until([&] { return r.running(); }, 100), 0);
  r.scan(10);
  ASSERT_TRUE(r.model->ossd(0));
  const Mac dev_mac = r.loop.devices[0].eth->mac();
  const Ipv4 dev_ip = r.loop.devices[0].dev->ip();
  r.loop.hub.set_link_up(dev_mac, false);
  r.loop.net.set_link_up(dev_ip, false);
  const int lost = r.scan_until([&] { return !r.loop.online(0); }, 50);
  ASSERT_GT(lost, 0);
  EXPECT_LE(lost, 4) << "within the data-hold time (3 x 1 ms)";
  const int qbad = r.scan_until([&] { return r.io.QBAD; }, 200);
  ASSERT_GT(qbad, 0);
  EXPECT_LE(lost + qbad, 101 + 1) << "passivated within F_WD_Time";
  r.scan(150);
  EXPECT_TRUE(r.all_safe()) << "host side safe, and the device's SO1-3 off";
  r.loop.hub.set_link_up(dev_mac, true);
  r.loop.net.set_link_up(dev_ip, true);
  ASSERT_GT(r.scan_until([&] { return r.loop.online(0); }, 3000), 0);
  r.expect_ack_reintegration();
  EXPECT_EQ(r.loop.ctrl->counters(0).losses, 1u);
}

}  // namespace

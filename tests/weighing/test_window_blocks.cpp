// The window-protocol blocks against the simulated PR5510 in virtual time:
// read (spec §3.5), write with Write_Active (§3.6), commands (§3.3 / §5.5),
// digital outputs (§3.3), status (§3.4), strings (§4.3), the arbitration
// of PR5510_Device, and timeouts / device errors as ErrorIDs.
#include <gtest/gtest.h>

#include <tuple>

#include "plc/fb/weighing/batch_weigh.hpp"
#include "plc/fb/weighing/command.hpp"
#include "plc/fb/weighing/digital_outputs.hpp"
#include "plc/fb/weighing/read_value.hpp"
#include "plc/fb/weighing/status.hpp"
#include "plc/fb/weighing/string_value.hpp"
#include "plc/fb/weighing/write_value.hpp"
#include "pr5510_cell.hpp"

namespace wg = plc::weighing;
namespace eid = plc::weighing::error_id;
using namespace std::chrono_literals;
using wtest::Cell;
using wtest::quiet_config;

namespace {

class BlocksBothBuses : public ::testing::TestWithParam<wg::Bus> {};

// Reads one code with a fresh ReadValue block; returns Value once Valid.
wg::PR5510_ReadValue read_once(Cell& c, std::uint8_t code) {
  wg::PR5510_ReadValue rv;
  rv.Device = &c.dev;
  rv.Enable = true;
  rv.Code = code;
  const auto t = c.run_until([&] { return rv.Valid || rv.Error; }, 1000ms, [&] { rv(c.ctx); });
  EXPECT_NE(-1ms, t) << "code " << int(code);
  EXPECT_FALSE(rv.Error) << "code " << int(code) << " ErrorID " << rv.ErrorID;
  rv.Enable = false;
  c.scan([&] { rv(c.ctx); });
  return rv;
}

// Runs an Execute block to Done or Error (at most `limit`).
template <class FB>
void execute(Cell& c, FB& fb, std::chrono::milliseconds limit = 10s) {
  fb.Execute = true;
  const auto t = c.run_until([&] { return fb.Done || fb.Error; }, limit, [&] { fb(c.ctx); });
  EXPECT_NE(-1ms, t);
  const bool done = fb.Done, error = fb.Error;
  const auto id = static_cast<std::uint16_t>(fb.ErrorID);
  fb.Execute = false;
  c.scan([&] { fb(c.ctx); });  // visible one more scan, then cleared
  EXPECT_FALSE(fb.Done || fb.Error);
  fb.Done = done;  // keep the result for the caller's assertions
  fb.Error = error;
  fb.ErrorID = id;
}

}  // namespace

// §7.2 start-up: the device block reads FSD (clearing Cal_Changed, §3.4),
// code 4 and code 5 by itself.
TEST_P(BlocksBothBuses, Spec72_DeviceStartUpReadsFsdFormatModel) {
  auto cfg = quiet_config(GetParam());
  Cell c(cfg);
  const auto t = c.run_until([&] { return c.dev.Ready && c.dev.Model != 0; }, 1000ms, [] {});
  ASSERT_NE(-1ms, t);
  EXPECT_EQ(5000, c.dev.FullScale);
  EXPECT_EQ(2, c.dev.Decimals);
  EXPECT_EQ(0x03, c.dev.Unit);
  EXPECT_EQ(1, c.dev.Division);
  EXPECT_EQ(0x5510, c.dev.Model);
  EXPECT_EQ(0x0312, c.dev.Version);
  c.idle(60ms);
  EXPECT_FALSE(c.dev.status().CalChanged);
  EXPECT_FLOAT_EQ(12.34f, c.dev.to_units(1234));
}

// §3.5 / §5.2: every firmware read code through PR5510_ReadValue.
TEST_P(BlocksBothBuses, Spec35_52_ReadValueEveryCode) {
  auto cfg = quiet_config(GetParam());
  cfg.filling.initial_load = 7.25;
  Cell c(cfg);
  c.idle(500ms);
  EXPECT_EQ(725, read_once(c, 0x08).Value);
  EXPECT_EQ(725, read_once(c, 0x09).Value);
  EXPECT_EQ(0, read_once(c, 0x0A).Value);
  EXPECT_EQ(72500, read_once(c, 0x0C).Value);
  EXPECT_EQ(5000, read_once(c, 0x0E).Value);
  EXPECT_EQ((wg::FormatInfo{2, 3, 1, 0}), wg::unpack_format(read_once(c, 0x04).Raw));
  EXPECT_EQ((wg::ModelInfo{0x5510, 0x0312}), wg::unpack_model(read_once(c, 0x05).Raw));
}

// §3.5 step 3: the value stays live while the code is unchanged.
TEST(Pr5510Blocks, Spec35_ReadValueStaysLive) {
  Cell c(quiet_config());
  wg::PR5510_ReadValue rv;
  rv.Device = &c.dev;
  rv.Enable = true;
  rv.Code = 0x08;
  c.run(500ms, [&] { rv(c.ctx); });
  ASSERT_TRUE(rv.Valid);
  EXPECT_EQ(0, rv.Value);
  c.model().process().add_load(3.0);
  c.run(500ms, [&] { rv(c.ctx); });
  EXPECT_EQ(300, rv.Value);
  EXPECT_TRUE(rv.Busy);
  EXPECT_GT(rv.Updates, 400u);  // refreshed every scan it held the window
}

// §3.6 / §4.1 / §4.2: DINT and REAL through the write handshake, read back.
TEST_P(BlocksBothBuses, Spec36_41_42_WriteValueDintAndReal) {
  Cell c(quiet_config(GetParam()));
  c.idle(100ms);
  wg::PR5510_WriteValue wv;
  wv.Device = &c.dev;
  wv.Code = 0x84;
  wv.Value = 4660;
  execute(c, wv);
  EXPECT_TRUE(wv.Done);
  EXPECT_EQ(4660, read_once(c, 0x84).Value);
  wv.Code = 0x85;
  wv.UseReal = true;
  wv.ValueReal = 200.0f;
  execute(c, wv);
  EXPECT_TRUE(wv.Done);
  const auto r = read_once(c, 0x85);
  EXPECT_FLOAT_EQ(200.0f, r.ValueReal);
  EXPECT_EQ(0x43480000u, static_cast<std::uint32_t>(r.Raw));
  EXPECT_FALSE(c.dev.status().WriteActive);  // handshake finished (step 6)
}

// PLCopen output rules: Done held while Execute stays TRUE.
TEST(Pr5510Blocks, ExecuteDoneHeldWhileExecuteHigh) {
  Cell c(quiet_config());
  c.idle(100ms);
  wg::PR5510_WriteValue wv;
  wv.Device = &c.dev;
  wv.Code = 0x20;
  wv.Value = 1;
  wv.Execute = true;
  c.run_until([&] { return wv.Done; }, 2s, [&] { wv(c.ctx); });
  ASSERT_TRUE(wv.Done);
  EXPECT_FALSE(wv.Busy);
  c.run(200ms, [&] { wv(c.ctx); });
  EXPECT_TRUE(wv.Done);
  wv.Execute = false;
  c.scan([&] { wv(c.ctx); });
  EXPECT_FALSE(wv.Done);
}

// §5.4: the firmware write codes through PR5510_WriteValue.
TEST(Pr5510Blocks, Spec54_WriteValueFirmwareCodes) {
  auto cfg = quiet_config();
  cfg.filling.initial_load = 0.5;
  Cell c(cfg);
  c.idle(500ms);
  wg::PR5510_WriteValue wv;
  wv.Device = &c.dev;
  auto send = [&](std::uint8_t code) {
    wv.Code = code;
    execute(c, wv);
    EXPECT_TRUE(wv.Done) << "code " << int(code) << " ErrorID " << wv.ErrorID;
  };
  send(0x70);
  EXPECT_EQ(0, c.model().gross_digits());
  c.model().process().add_load(4.0);
  c.idle(500ms);
  send(0x71);
  EXPECT_TRUE(c.model().status().TareActive);
  EXPECT_EQ(400, c.model().tare_digits());
  send(0x72);
  EXPECT_FALSE(c.model().status().TareActive);
  send(0x73);
  EXPECT_TRUE(c.model().status().TestActive);
  send(0x74);
  EXPECT_FALSE(c.model().status().TestActive);
  send(0x75);
  EXPECT_FALSE(c.model().status().PowerFail);
  // Undefined code: refused by the block before it reaches the device.
  wv.Code = 0x40;
  execute(c, wv);
  EXPECT_TRUE(wv.Error);
  EXPECT_EQ(eid::kInvalidCode, wv.ErrorID);
}

// §5.3 error 33 via the write path: Cmd_Error -> ErrorID 16#8121.
TEST(Pr5510Blocks, Spec53_WriteValueDeviceErrorNumber) {
  auto cfg = quiet_config();
  cfg.legal_for_trade = true;
  Cell c(cfg);
  c.model().process().add_load(-0.3);
  c.idle(500ms);
  wg::PR5510_WriteValue wv;
  wv.Device = &c.dev;
  wv.Code = 0x71;
  execute(c, wv);
  EXPECT_TRUE(wv.Error);
  EXPECT_EQ(eid::kDeviceErrorBase + 33, wv.ErrorID);
  EXPECT_EQ(33, c.dev.LastError);
}

// §3.3 / §5.5: every W[7] command through PR5510_Command, edges >= 40 ms.
TEST_P(BlocksBothBuses, Spec33_55_CommandEveryBit) {
  auto cfg = quiet_config(GetParam());
  cfg.filling.initial_load = 0.2;
  Cell c(cfg);
  c.idle(500ms);
  wg::PR5510_Command cmd;
  cmd.Device = &c.dev;
  // Watch the edge length on the wire.
  int high_ms = 0, longest = 0;
  auto body = [&] { cmd(c.ctx); };
  auto run_cmd = [&](wg::CommandBit b) {
    cmd.Command = b;
    cmd.Execute = true;
    high_ms = longest = 0;
    c.run_until([&] { return cmd.Done || cmd.Error; }, 5s,
                [&] {
                  body();
                  high_ms = c.sim.w()[wg::w::kCommands] ? high_ms + 1 : 0;
                  longest = std::max(longest, high_ms);
                });
    EXPECT_TRUE(cmd.Done) << "bit " << int(b) << " ErrorID " << cmd.ErrorID;
    EXPECT_GE(longest, 40);  // §3.3: hold at least 40 ms
    cmd.Execute = false;
    c.run(100ms, body);
  };
  run_cmd(wg::CommandBit::SetZero);
  EXPECT_EQ(0, c.model().gross_digits());
  c.model().process().add_load(2.0);
  c.idle(500ms);
  run_cmd(wg::CommandBit::SetTare);
  EXPECT_TRUE(c.dev.status().TareActive);
  run_cmd(wg::CommandBit::ResTare);
  EXPECT_FALSE(c.dev.status().TareActive);
  run_cmd(wg::CommandBit::SetTest);
  EXPECT_TRUE(c.dev.status().TestActive);
  run_cmd(wg::CommandBit::ResTest);
  EXPECT_FALSE(c.dev.status().TestActive);
  run_cmd(wg::CommandBit::ResPower);
  EXPECT_FALSE(c.dev.status().PowerFail);
}

// §5.3 errors 31 (tare without standstill) and 47 (zero outside range) as
// ErrorIDs 16#811F and 16#812F.
TEST(Pr5510Blocks, Spec53_CommandDeviceErrors31And47) {
  auto cfg = quiet_config();
  cfg.filling.initial_load = 5.0;
  Cell c(cfg);
  c.idle(500ms);
  wg::PR5510_Command cmd;
  cmd.Device = &c.dev;
  cmd.Command = wg::CommandBit::SetZero;
  execute(c, cmd);
  EXPECT_TRUE(cmd.Error);
  EXPECT_EQ(eid::kDeviceErrorBase + 47, cmd.ErrorID);
  c.dev.set_output(wg::OutputBit::Out2, true);  // fine feed keeps it moving
  c.idle(800ms);                                // past the fall time and the standstill window
  cmd.Command = wg::CommandBit::SetTare;
  cmd.Execute = true;
  c.run(500ms, [&] { cmd(c.ctx); });
  EXPECT_TRUE(cmd.Busy);  // Cmd_Busy: waiting for standstill
  c.run_until([&] { return cmd.Done || cmd.Error; }, 5s, [&] { cmd(c.ctx); });
  EXPECT_TRUE(cmd.Error);
  EXPECT_EQ(eid::kDeviceErrorBase + 31, cmd.ErrorID);
}

// §5.3 error 42: a tare while an operator calibrates at the front panel
// ends the command with ErrorID 16#812A; after calibration it works.
TEST(Pr5510Blocks, Spec53_TareDuringPanelCalibrationIsError42) {
  Cell c(quiet_config());
  c.idle(500ms);
  ASSERT_TRUE(c.model().panel_start_calibration());
  wg::PR5510_Command cmd;
  cmd.Device = &c.dev;
  cmd.Command = wg::CommandBit::SetTare;
  execute(c, cmd);
  EXPECT_TRUE(cmd.Error);
  EXPECT_EQ(eid::kDeviceErrorBase + 42, cmd.ErrorID);
  ASSERT_TRUE(c.model().panel_finish_calibration());
  execute(c, cmd);
  EXPECT_TRUE(cmd.Done) << "ErrorID 16#" << std::hex << cmd.ErrorID;
  EXPECT_TRUE(c.model().status().TareActive);
}

// §3.3 W[6] / §3.4 R[5].3-5 and the 24 named bits of PR5510_Status.
TEST(Pr5510Blocks, Spec33_34_DigitalOutputsAndStatus) {
  Cell c(quiet_config());
  wg::PR5510_DigitalOutputs dout;
  dout.Device = &c.dev;
  dout.Enable = true;
  dout.Out2 = true;
  dout.Out3 = true;
  wg::PR5510_Status stat;
  stat.Device = &c.dev;
  c.model().set_input(1, true);
  c.run(100ms, [&] {
    dout(c.ctx);
    stat(c.ctx);
  });
  EXPECT_FALSE(dout.Out1State);
  EXPECT_TRUE(dout.Out2State);
  EXPECT_TRUE(dout.Out3State);
  EXPECT_TRUE(stat.Valid);
  const wg::StatusBits& m = c.model().status();
  EXPECT_EQ(m.Out2, stat.Out2);
  EXPECT_TRUE(stat.Inp1);
  EXPECT_TRUE(stat.PowerFail);
  EXPECT_FALSE(stat.CalChanged);  // cleared by the device block's FSD read
  EXPECT_TRUE(stat.CenterZero);
  EXPECT_EQ(c.dev.StatusByte, c.sim.r()[5]);
  EXPECT_EQ(c.dev.WeighingByte, c.sim.r()[7]);
}

// §4.3: a 20-character STRING as 5 x 4 characters, both buses.
TEST_P(BlocksBothBuses, Spec43_StringWriteAndReadBack) {
  Cell c(quiet_config(GetParam()));
  c.idle(100ms);
  wg::PR5510_WriteString ws;
  ws.Device = &c.dev;
  ws.BaseCode = 0x90;
  ws.Text = "FLOUR TYPE 550 LOT7";
  execute(c, ws);
  EXPECT_TRUE(ws.Done);
  wg::PR5510_ReadString rs;
  rs.Device = &c.dev;
  rs.BaseCode = 0x90;
  execute(c, rs);
  EXPECT_TRUE(rs.Done);
  EXPECT_EQ(std::string_view("FLOUR TYPE 550 LOT7"), rs.Text.view());
}

// Arbitration: three readers, a writer and a command on one device at
// once; every reader only ever sees values of its own code.
TEST(Pr5510Blocks, ArbitrationSharesTheWindows) {
  auto cfg = quiet_config();
  cfg.filling.initial_load = 12.34;
  Cell c(cfg);
  c.idle(500ms);
  std::array<wg::PR5510_ReadValue, 3> rv;
  const std::uint8_t codes[3] = {0x08, 0x0C, 0x0E};
  const std::int32_t expect[3] = {1234, 123400, 5000};
  for (int i = 0; i < 3; ++i) {
    rv[i].Device = &c.dev;
    rv[i].Enable = true;
    rv[i].Code = codes[i];
  }
  wg::PR5510_WriteValue wv;
  wv.Device = &c.dev;
  wv.Code = 0x30;
  wv.Value = 99;
  wv.Execute = true;
  wg::PR5510_Command cmd;
  cmd.Device = &c.dev;
  cmd.Command = wg::CommandBit::ResPower;
  cmd.Execute = true;
  int wrong = 0;
  c.run(3s, [&] {
    for (int i = 0; i < 3; ++i) {
      rv[i](c.ctx);
      if (rv[i].Valid && rv[i].Value != expect[i]) ++wrong;
    }
    wv(c.ctx);
    cmd(c.ctx);
  });
  EXPECT_EQ(0, wrong);
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(rv[i].Valid) << i;
    EXPECT_GT(rv[i].Updates, 10u) << i;  // everybody got turns
    EXPECT_FALSE(rv[i].Error) << i;
  }
  EXPECT_TRUE(wv.Done);
  EXPECT_TRUE(cmd.Done);
  EXPECT_FALSE(c.model().status().PowerFail);
  EXPECT_EQ(99, read_once(c, 0x30).Value);
  EXPECT_GT(c.dev.ReadGrants, 30u);
}

// Timeouts as ErrorIDs: no echo (read), no Write_Active (write), no effect
// (command) on a device whose scale interface is disabled.
TEST(Pr5510Blocks, TimeoutsAsErrorIds) {
  auto cfg = quiet_config();
  cfg.scale_interface = false;
  Cell c(cfg);
  c.dev.WriteTimeout = 1s;
  wg::PR5510_ReadValue rv;
  rv.Device = &c.dev;
  rv.Enable = true;
  rv.Code = 0x09;
  const auto t = c.run_until([&] { return rv.Error; }, 2s, [&] { rv(c.ctx); });
  EXPECT_GE(t, 500ms);  // EchoTimeout
  EXPECT_EQ(eid::kReadEchoTimeout, rv.ErrorID);
  wg::PR5510_WriteValue wv;
  wv.Device = &c.dev;
  wv.Code = 0x20;
  execute(c, wv);
  EXPECT_TRUE(wv.Error);
  EXPECT_EQ(eid::kWriteAckTimeout, wv.ErrorID);
  wg::PR5510_Command cmd;
  cmd.Device = &c.dev;
  cmd.Command = wg::CommandBit::SetTare;
  execute(c, cmd);
  EXPECT_TRUE(cmd.Error);
  EXPECT_EQ(eid::kCommandNoEffect, cmd.ErrorID);
}

// A device that stops answering: blocks report kDeviceOffline; reads
// recover after Enable is cycled once the device is back.
TEST(Pr5510Blocks, OfflineAndRecovery) {
  Cell c(quiet_config());
  wg::PR5510_ReadValue rv;
  rv.Device = &c.dev;
  rv.Enable = true;
  rv.Code = 0x08;
  c.run(200ms, [&] { rv(c.ctx); });
  ASSERT_TRUE(rv.Valid);
  c.model().set_answering(false);
  c.run(50ms, [&] { rv(c.ctx); });
  EXPECT_TRUE(rv.Error);
  EXPECT_EQ(eid::kDeviceOffline, rv.ErrorID);
  EXPECT_FALSE(c.dev.Online);
  wg::PR5510_WriteValue wv;
  wv.Device = &c.dev;
  wv.Code = 0x20;
  execute(c, wv);
  EXPECT_EQ(eid::kDeviceOffline, wv.ErrorID);
  c.model().set_answering(true);
  rv.Enable = false;
  c.run(10ms, [&] { rv(c.ctx); });
  rv.Enable = true;
  c.run(300ms, [&] { rv(c.ctx); });
  EXPECT_TRUE(rv.Valid);
  EXPECT_FALSE(rv.Error);
  EXPECT_TRUE(c.dev.Ready);
}

// No device and no free slot are errors, not crashes.
TEST(Pr5510Blocks, NoDeviceAndTooManyClients) {
  wg::PR5510_ReadValue rv;
  rv.Enable = true;
  rv.Code = 0x08;
  plc::ScanContext ctx{};
  rv(ctx);
  EXPECT_EQ(eid::kNoDevice, rv.ErrorID);
  Cell c(quiet_config());
  std::array<wg::PR5510_ReadValue, wg::PR5510_Device::kMaxClients> many;
  for (auto& r : many) {
    r.Device = &c.dev;
    r.Enable = true;
    r.Code = 0x08;
  }
  c.run(20ms, [&] {
    for (auto& r : many) r(c.ctx);
  });
  EXPECT_EQ(eid::kTooManyClients, many.back().ErrorID);  // slot 0 is the device's own
  EXPECT_FALSE(many.front().Error);
}

// §7.2: re-read code 4 and FSD whenever Cal_Changed rises again (here
// after a power cycle of the device, which sets it, §3.4).
TEST(Pr5510Blocks, Spec72_RereadOnCalChanged) {
  Cell c(quiet_config());
  c.idle(300ms);
  ASSERT_TRUE(c.dev.Ready);
  const auto reads = c.dev.FormatReads;
  c.model().power_cycle();
  c.idle(25ms);
  EXPECT_TRUE(c.dev.status().CalChanged);  // the device block saw it rise
  EXPECT_EQ(reads, c.dev.FormatReads);
  c.idle(300ms);
  EXPECT_GT(c.dev.FormatReads, reads);
  EXPECT_FALSE(c.model().status().CalChanged);  // cleared by the FSD read
  EXPECT_TRUE(c.dev.Ready);
}

// A reader that changes its code gets only values of the new code after
// the new echo (§7.2 Read step 6: ignore R[0..3] until the echo matches).
TEST(Pr5510Blocks, Spec72_CodeChangeWaitsForEcho) {
  auto cfg = quiet_config();
  cfg.filling.initial_load = 1.0;
  Cell c(cfg);
  wg::PR5510_ReadValue rv;
  rv.Device = &c.dev;
  rv.Enable = true;
  rv.Code = 0x08;
  c.run(200ms, [&] { rv(c.ctx); });
  ASSERT_EQ(100, rv.Value);
  rv.Code = 0x0E;
  int stale = 0;
  c.run(200ms, [&] {
    rv(c.ctx);
    if (rv.Valid && rv.Value != 5000) ++stale;
  });
  EXPECT_EQ(0, stale);
  EXPECT_EQ(5000, rv.Value);
}

// §7.2 Write step 3 with a "Seperate" (non-consistent) module: the value
// is on the wire a device cycle before the code.
TEST(Pr5510Blocks, Spec72_SeparateModuleValueBeforeCode) {
  Cell c(quiet_config());
  c.dev.ConsistentModule = false;
  c.idle(100ms);
  wg::PR5510_WriteValue wv;
  wv.Device = &c.dev;
  wv.Code = 0x84;
  wv.Value = 4660;
  wv.Execute = true;
  int value_first_ms = -1, code_at_ms = -1;
  for (int t = 0; t < 500 && !wv.Done; ++t) {
    c.scan([&] { wv(c.ctx); });
    if (value_first_ms < 0 && c.sim.w()[3] == 0x34) value_first_ms = t;
    if (code_at_ms < 0 && c.sim.w()[wg::w::kWriteValueSelect] == 0x84) code_at_ms = t;
  }
  EXPECT_TRUE(wv.Done);
  ASSERT_GE(value_first_ms, 0);
  EXPECT_GE(code_at_ms - value_first_ms, 20);
  EXPECT_EQ(4660, read_once(c, 0x84).Value);
}

// §3.3: a CommandHold set below 40 ms still holds the edge 40 ms.
TEST(Pr5510Blocks, Spec33_CommandHoldNeverBelow40ms) {
  Cell c(quiet_config());
  c.dev.CommandHold = 10ms;
  c.idle(100ms);
  wg::PR5510_Command cmd;
  cmd.Device = &c.dev;
  cmd.Command = wg::CommandBit::ResPower;
  cmd.Execute = true;
  int high = 0;
  c.run_until([&] { return cmd.Done || cmd.Error; }, 2s,
              [&] {
                cmd(c.ctx);
                if (c.sim.w()[wg::w::kCommands]) ++high;
              });
  EXPECT_TRUE(cmd.Done);
  EXPECT_GE(high, 40);
  EXPECT_LE(high, 41);
}

INSTANTIATE_TEST_SUITE_P(Pr5510Blocks, BlocksBothBuses,
                         ::testing::Values(wg::Bus::Profibus, wg::Bus::DeviceNet));

// Issue 10 point 5: Busy is an interface output that the debugger or the HMI
// may still write. A block made Busy from outside has no job: no arbitration
// slot (slot_ = kNoSlot), no device, or every string chunk done already. It
// must end with an error instead of indexing the device's per-slot arrays
// with the missing slot or writing past its string buffer.
TEST(Pr5510Blocks, BusySetFromOutsideEndsWithAnErrorAndIndexesNothing) {
  Cell c(quiet_config());
  c.idle(100ms);
  wg::PR5510_ReadString rs;
  wg::PR5510_WriteString ws;
  wg::PR5510_WriteValue wv;
  wg::PR5510_Command cmd;
  wg::PR5510_BatchWeigh bw;
  rs.Device = ws.Device = wv.Device = cmd.Device = bw.Device = &c.dev;
  rs.Busy = ws.Busy = wv.Busy = cmd.Busy = bw.Busy = true;
  c.scan([&] {
    rs(c.ctx);
    ws(c.ctx);
    wv(c.ctx);
    cmd(c.ctx);
    bw(c.ctx);
  });
  for (auto [name, busy, error, id] :
       {std::tuple{"ReadString", rs.Busy, rs.Error, std::uint16_t(rs.ErrorID)},
        std::tuple{"WriteString", ws.Busy, ws.Error, std::uint16_t(ws.ErrorID)},
        std::tuple{"WriteValue", wv.Busy, wv.Error, std::uint16_t(wv.ErrorID)},
        std::tuple{"Command", cmd.Busy, cmd.Error, std::uint16_t(cmd.ErrorID)},
        std::tuple{"BatchWeigh", bw.Busy, bw.Error, std::uint16_t(bw.ErrorID)}}) {
    EXPECT_FALSE(busy) << name;
    EXPECT_TRUE(error) << name;
    EXPECT_EQ(eid::kNoJob, id) << name;
  }
  EXPECT_EQ(c.dev.read_error(wg::PR5510_Device::kNoSlot), eid::kNoJob);
  EXPECT_EQ(c.dev.write_status(-2147483647 - 1), wg::WriteStatus::Error);
  EXPECT_EQ(c.dev.command_error(wg::PR5510_Device::kMaxClients), eid::kNoJob);

  // No device at all.
  wg::PR5510_ReadString rs0;
  wg::PR5510_WriteValue wv0;
  wg::PR5510_BatchWeigh bw0;
  rs0.Busy = wv0.Busy = bw0.Busy = true;
  rs0(c.ctx);
  wv0(c.ctx);
  bw0(c.ctx);
  EXPECT_EQ(eid::kNoDevice, rs0.ErrorID);
  EXPECT_EQ(eid::kNoDevice, wv0.ErrorID);
  EXPECT_EQ(eid::kNoDevice, bw0.ErrorID);

  // A string read that is done: Busy again must not read a sixth chunk
  // into the 20-character buffer.
  wg::PR5510_WriteString w;
  w.Device = &c.dev;
  w.BaseCode = 0x90;
  w.Text = "ABCDEFGHIJKLMNOPQRST";
  execute(c, w);
  ASSERT_TRUE(w.Done);
  wg::PR5510_ReadString r;
  r.Device = &c.dev;
  r.BaseCode = 0x90;
  execute(c, r);
  ASSERT_TRUE(r.Done);
  r.Busy = true;
  c.scan([&] { r(c.ctx); });
  EXPECT_FALSE(r.Busy);
  EXPECT_TRUE(r.Error);
  EXPECT_EQ(eid::kNoJob, r.ErrorID);
  EXPECT_EQ(std::string_view("ABCDEFGHIJKLMNOPQRST"), r.Text.view());
}

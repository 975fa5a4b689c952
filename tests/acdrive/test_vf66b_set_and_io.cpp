// The simulated VF66B against the access column of the manual's attribute
// tables (toyo-vf66-devicenet.md §4-§6, checked against the Japanese
// original, seed 002: Tables 3.3.2, 3.4.2, 3.5.2), the power-up NetRef of
// the manual's section 4.1 (spec §9.2), and which write wins when an
// explicit Set and an output message write the same datum (the reading in
// vf66b_model.hpp).
#include <gtest/gtest.h>

#include <vector>

#include "vf66b_explicit_harness.hpp"

namespace plc::sim {

using namespace std::chrono_literals;
using acdrive::DriveState;
using test::Bytes;
using test::Drive;

namespace {

enum class Access : std::uint8_t { Get, SetGet };
// One row of a table: attribute, access rule, "Support", data size.
struct Row {
  std::uint8_t attr;
  Access access;
  bool supported;
  std::size_t size;
};
constexpr Access G = Access::Get, SG = Access::SetGet;

// Table 3.3.2 (Motor Data 0x28), rows as printed (sizes of the supported
// ones: USINT 1, UINT 2).
const std::vector<Row> kMotorData = {
    {1, G, false, 1},   {2, G, false, 1},   {3, SG, true, 1},   {4, SG, false, 1},
    {5, SG, false, 1},  {6, SG, true, 2},   {7, SG, true, 2},   {8, SG, false, 1},
    {9, SG, false, 1},  {10, SG, false, 1}, {11, SG, false, 1}, {12, SG, false, 1},
    {13, SG, false, 1}, {14, SG, false, 1}, {15, SG, false, 1}, {19, SG, false, 1}};
// Table 3.4.2 (Control Supervisor 0x29).
const std::vector<Row> kControlSupervisor = {
    {1, G, false, 1},   {2, G, false, 1},   {3, SG, true, 1},  {4, SG, true, 1},  {5, SG, true, 1},
    {6, G, true, 1},    {7, G, true, 1},    {8, G, true, 1},   {9, G, true, 1},   {10, G, true, 1},
    {11, G, true, 1},   {12, SG, true, 1},  {13, G, false, 2}, {14, G, false, 2}, {15, G, true, 1},
    {16, SG, false, 1}, {17, SG, false, 1}, {18, G, false, 1}};
// Table 3.5.2 (AC/DC Drive 0x2A; the manual writes "Get/Set").
const std::vector<Row> kAcDcDrive = {
    {1, G, false, 1},   {2, G, false, 1},   {3, G, true, 1},    {4, SG, true, 1},
    {5, SG, false, 1},  {6, SG, true, 1},   {7, G, true, 2},    {8, SG, true, 2},
    {9, G, false, 2},   {10, SG, false, 2}, {11, G, false, 2},  {12, SG, false, 2},
    {13, G, false, 2},  {14, SG, false, 2}, {15, G, false, 2},  {16, G, false, 2},
    {17, G, false, 2},  {18, SG, false, 2}, {19, SG, false, 2}, {20, SG, false, 2},
    {21, SG, false, 2}, {22, SG, true, 1},  {23, SG, false, 1}, {24, SG, false, 1},
    {25, SG, false, 1}, {26, SG, false, 1}, {27, SG, false, 1}, {28, SG, false, 1},
    {29, G, true, 1},   {30, G, false, 1},  {31, SG, false, 1}, {32, SG, false, 2},
    {33, SG, false, 2}, {34, SG, false, 1}, {35, G, false, 2},  {36, SG, false, 2}};

void check_table(Drive& d, std::uint8_t cls, const std::vector<Row>& rows, unsigned j09) {
  for (const Row& r : rows) {
    SCOPED_TRACE(testing::Message() << "class 0x" << std::hex << int(cls) << std::dec << " attr "
                                    << int(r.attr) << ", J-09 = " << j09);
    const auto got = d.get(cls, 1, r.attr);
    if (!r.supported) {
      EXPECT_EQ(got.general(), 0x14) << "Not Support: Get";
      EXPECT_EQ(d.set(cls, 1, r.attr, Bytes(r.size, 0)).general(), 0x14) << "Not Support: Set";
      continue;
    }
    ASSERT_EQ(got.general(), 0) << "Support: Get";
    EXPECT_EQ(got.data.size(), r.size);
    if (r.access == G) {
      EXPECT_EQ(d.set(cls, 1, r.attr, got.data).general(), 0x0E) << "Get only";
    } else {
      // Writing back the value read is valid for every Set/Get attribute
      // (DriveMode accepts only the inverter's mode, which it reads).
      EXPECT_EQ(d.set(cls, 1, r.attr, got.data).general(), 0) << "Set/Get, Support";
      EXPECT_EQ(d.get(cls, 1, r.attr).data, got.data);
    }
  }
}

}  // namespace

// Every attribute of the three tables, in the three kinds of output
// assembly (20, 21 with NetCtrl/NetRef, 100 extended): a Set/Get "Support"
// attribute takes Set_Attribute_Single whatever the output assembly carries
// (Run1, Run2, NetCtrl, FaultRst, NetRef, SpeedRef included); a Get one
// answers 0x0E, a "Not Support" one 0x14 (§11.1 usual practice).
TEST(Vf66bSetAndIo, AccessColumnOfTable3_3_2_Table3_4_2_Table3_5_2) {
  for (unsigned j09 : {0U, 1U, 2U}) {
    Drive d(j09, j09 == 2 ? 2 : j09);
    check_table(d, 0x28, kMotorData, j09);
    check_table(d, 0x29, kControlSupervisor, j09);
    check_table(d, 0x2A, kAcDcDrive, j09);
  }
}

// Table 3.4.2 row 12: FaultRst is Set/Get, 0->1 = fault reset, 0 = no
// action. The edge counts when it is written, so an explicit reset works
// even when the next output message (the sim plugin's, every step) carries
// Fault Reset = 0.
TEST(Vf66bSetAndIo, FaultRstSetResetsAFault_Table3_4_2) {
  Drive d(1, 1);
  d.out = {0x60, 0, 0, 0};  // NetCtrl, NetRef, no run, no reset
  d.m->trip(7);
  d.step(5);
  ASSERT_EQ(d.m->state(), DriveState::Faulted);
  EXPECT_EQ(d.set(0x29, 1, 12, {1}).general(), 0);
  d.step();
  EXPECT_EQ(d.m->state(), DriveState::Ready);
  EXPECT_FALSE(d.m->faulted());
  // The same through Parameter instance 11 "Fault Reset" (Table 3.2).
  d.m->trip(7);
  d.step(5);
  ASSERT_EQ(d.m->state(), DriveState::Faulted);
  EXPECT_EQ(d.set(0x0F, 11, 1, {1}).general(), 0);
  d.step();
  EXPECT_EQ(d.m->state(), DriveState::Ready);
}

// Table 3.4.2 row 12 without output messages (a DeviceNet master with only
// the explicit connection, or between polls): a held 1 is no reset, a new
// 0->1 is.
TEST(Vf66bSetAndIo, FaultRstActsOnTheRisingEdgeOnly_Table3_4_2) {
  Drive d(0, 0);
  d.m->trip(7);
  d.idle(5);
  ASSERT_EQ(d.m->state(), DriveState::Faulted);
  EXPECT_EQ(d.set(0x29, 1, 12, {1}).general(), 0);
  d.idle();
  EXPECT_EQ(d.m->state(), DriveState::Ready);
  EXPECT_EQ(d.get(0x29, 1, 12).data, Bytes{1}) << "FaultRst reads what was written";
  d.m->trip(7);
  d.idle(5);
  EXPECT_EQ(d.set(0x29, 1, 12, {1}).general(), 0);
  d.idle();
  EXPECT_EQ(d.m->state(), DriveState::Faulted) << "1 -> 1 is no action";
  EXPECT_EQ(d.set(0x29, 1, 12, {0}).general(), 0);
  EXPECT_EQ(d.set(0x29, 1, 12, {1}).general(), 0);
  d.idle();
  EXPECT_EQ(d.m->state(), DriveState::Ready);
}

// Table 3.4.2 row 3 (Run1) and Table 3.5.2 row 8 (SpeedRef), Set/Get and
// supported: set explicitly, with no output message overwriting them, they
// run the drive (event matrix Table 3.4.3) at the reference (§6.1).
TEST(Vf66bSetAndIo, Run1AndSpeedRefSetRunTheDrive_Table3_4_2_Table3_5_2) {
  Drive d(0, 0);  // 20/70: Run1 and SpeedRef are both in output 20
  EXPECT_EQ(d.set(0x2A, 1, 8, {0x20, 0x1C}).general(), 0) << "7200 = 900 r/min at scale 3";
  EXPECT_EQ(d.set(0x29, 1, 3, {1}).general(), 0);
  d.idle();
  EXPECT_EQ(d.m->state(), DriveState::Enabled) << "Run1 0->1: Run";
  d.idle(600);
  EXPECT_DOUBLE_EQ(d.m->speed_rpm(), 900);
  EXPECT_EQ(d.get(0x29, 1, 3).data, Bytes{1});
  EXPECT_EQ(d.get(0x2A, 1, 8).data, (Bytes{0x20, 0x1C}));
  EXPECT_EQ(d.get(0x2A, 1, 3).data, Bytes{1}) << "AtReference";
  EXPECT_EQ(d.set(0x29, 1, 3, {0}).general(), 0);
  d.idle();
  EXPECT_EQ(d.m->state(), DriveState::Stopping) << "Run1 = Run2 = 0: Stop";
}

// Table 3.4.2 rows 4/5, Table 3.5.2 row 4: Run2, NetCtrl and NetRef are
// Set/Get also with output 21, which carries them; a Set stands until the
// next output message.
TEST(Vf66bSetAndIo, Run2NetCtrlNetRefSetWithOutput21_Table3_4_2_Table3_5_2) {
  Drive d(1, 1);
  d.out = {0x60, 0, 0x00, 0x10};  // NetCtrl, NetRef, 0x1000 = 512 r/min
  d.step();
  EXPECT_EQ(d.set(0x29, 1, 4, {1}).general(), 0) << "Run2";
  d.idle(400);
  EXPECT_EQ(d.m->state(), DriveState::Enabled);
  EXPECT_DOUBLE_EQ(d.m->speed_rpm(), -512);
  EXPECT_EQ(d.set(0x29, 1, 5, {0}).general(), 0) << "NetCtrl";
  d.idle();
  EXPECT_EQ(d.get(0x29, 1, 15).data, Bytes{0}) << "CtrlFromNet follows the request";
  EXPECT_EQ(d.m->state(), DriveState::Stopping) << "no network run command: Stop";
  EXPECT_EQ(d.set(0x2A, 1, 4, {0}).general(), 0) << "NetRef";
  d.idle();
  EXPECT_EQ(d.get(0x2A, 1, 29).data, Bytes{0}) << "RefFromNet follows the request";
  d.step();  // the next output message: NetCtrl = NetRef = 1, Run2 = 0
  EXPECT_EQ(d.get(0x29, 1, 5).data, Bytes{1});
  EXPECT_EQ(d.get(0x2A, 1, 4).data, Bytes{1});
  EXPECT_EQ(d.get(0x29, 1, 4).data, Bytes{0});
}

// Output 20 has no NetCtrl bit and no Run2 bit (Table 3.7.1): the objects
// are the only way to write them, and the output messages leave them alone.
TEST(Vf66bSetAndIo, NetCtrlAndRun2ThroughTheObjectsWithOutput20_Table3_7_1) {
  Drive d(0, 0);
  EXPECT_EQ(d.set(0x29, 1, 5, {0}).general(), 0);
  d.step();
  EXPECT_EQ(d.get(0x29, 1, 15).data, Bytes{0}) << "CtrlFromNet follows the request";
  EXPECT_EQ(d.set(0x29, 1, 5, {1}).general(), 0);
  d.out = {0, 0, 0x00, 0x10};  // Run1 = 0, 512 r/min
  EXPECT_EQ(d.set(0x29, 1, 4, {1}).general(), 0);
  d.step(400);
  EXPECT_EQ(d.m->state(), DriveState::Enabled) << "Run2 0->1 with Run1 = 0 from output 20";
  EXPECT_DOUBLE_EQ(d.m->speed_rpm(), -512);
}

// Which wins (vf66b_model.hpp): the last write. An explicit Set stands
// until the next output message; that message overwrites it.
TEST(Vf66bSetAndIo, LastWriteWinsBetweenSetAndOutputMessage_Table3_5_2_Table3_7_1) {
  Drive d(1, 1);
  d.out = {0x61, 0, 0xA0, 0x0F};  // Run1, NetCtrl, NetRef; 4000 = 500 r/min
  d.step();
  EXPECT_EQ(d.set(0x2A, 1, 8, {0x40, 0x1F}).general(), 0) << "8000 = 1000 r/min";
  d.idle(1000);
  EXPECT_DOUBLE_EQ(d.m->speed_rpm(), 1000) << "the Set stands between output messages";
  EXPECT_EQ(d.get(0x2A, 1, 8).data, (Bytes{0x40, 0x1F}));
  d.step();  // a new output message
  EXPECT_EQ(d.get(0x2A, 1, 8).data, (Bytes{0xA0, 0x0F})) << "the message overwrote the Set";
  d.idle(1000);
  EXPECT_DOUBLE_EQ(d.m->speed_rpm(), 500);
  // Run1 likewise: 0 by Set stops, the next message's Run1 = 1 (0 -> 1
  // again) runs.
  EXPECT_EQ(d.set(0x29, 1, 3, {0}).general(), 0);
  d.idle();
  EXPECT_EQ(d.m->state(), DriveState::Stopping);
  d.step();
  EXPECT_EQ(d.m->state(), DriveState::Enabled);
  // The sim plugin's outputs are a new message at every step: a Set is
  // overwritten in the same step.
  EXPECT_EQ(d.set(0x2A, 1, 8, {0x40, 0x1F}).general(), 0);
  d.step(1000);
  EXPECT_DOUBLE_EQ(d.m->speed_rpm(), 500);
}

// Extended output 100 (Table 6.2): Start/Rev and Speed Reference2 are the
// run command and reference that Run1/Run2 and SpeedRef also write; the
// last write wins here too. SpeedRef reads and writes the reference in
// r/min x 2^SpeedScale (§6.1).
TEST(Vf66bSetAndIo, RunAndSpeedRefSetWithExtendedOutput100_Table3_4_2_Table6_2) {
  Drive d(2, 2);  // 100/120
  EXPECT_EQ(d.set(0x2A, 1, 8, {0x20, 0x1C}).general(), 0) << "900 r/min";
  EXPECT_EQ(d.set(0x29, 1, 4, {1}).general(), 0) << "Run2";
  d.idle(1000);
  EXPECT_DOUBLE_EQ(d.m->speed_rpm(), -900);
  EXPECT_EQ(d.get(0x2A, 1, 8).data, (Bytes{0x20, 0x1C}));
  // Start forward, Speed Reference2 5000 = 450 r/min (top 1800).
  d.out = {0x01, 0, 0, 0, 0x88, 0x13, 0, 0};
  d.step();
  EXPECT_EQ(d.get(0x29, 1, 3).data, Bytes{1}) << "Start, Rev off = Run1";
  EXPECT_EQ(d.get(0x29, 1, 4).data, Bytes{0});
  EXPECT_EQ(d.get(0x2A, 1, 8).data, (Bytes{0x10, 0x0E})) << "450 x 8 = 3600";
  d.idle(2000);
  EXPECT_DOUBLE_EQ(d.m->speed_rpm(), 450);
}

// Manual section 4.1 (spec §9.2, Table 4.3 notes): at power-up the card
// sets its speed-reference location, 0x2A attr 4 NetRef, to network when
// b-10 = 3 and to local otherwise. Parameter 14 "Network Ref" (Table 3.2)
// mirrors it; RefFromNet (attr 29) is 0 without b-10 = 3.
TEST(Vf66bSetAndIo, NetRefAtPowerUpIsNetworkOnlyWithB10_3_Section4_1) {
  for (unsigned b10 = 0; b10 <= 7; ++b10) {
    SCOPED_TRACE(testing::Message() << "b-10 = " << b10);
    auto c = acdrive::test::net_config(0, 0);  // output 20 carries no NetRef bit
    c.b10 = b10;
    Drive d(c);
    const Bytes want{static_cast<std::uint8_t>(b10 == 3)};
    EXPECT_EQ(d.get(0x2A, 1, 4).data, want) << "NetRef";
    EXPECT_EQ(d.get(0x0F, 14, 1).data, want) << "Parameter 14 Network Ref";
    EXPECT_EQ(d.get(0x2A, 1, 29).data, want) << "RefFromNet";
  }
  // b-10 is read at power-up only (§9.1).
  Drive d(acdrive::test::net_config(0, 0));
  d.m->settings().b10 = 0;
  EXPECT_EQ(d.get(0x2A, 1, 4).data, Bytes{1});
  d.m->power_cycle();
  EXPECT_EQ(d.get(0x2A, 1, 4).data, Bytes{0});
  // Without b-10 = 3 the master's reference stays ignored even when it
  // requests it.
  EXPECT_EQ(d.set(0x2A, 1, 4, {1}).general(), 0);
  d.step(20);
  EXPECT_EQ(d.get(0x2A, 1, 29).data, Bytes{0});
}

// [reading] §13.4 item 14, by analogy with section 4.1: NetCtrl (0x29 attr
// 5, Parameter 4 "Network Control") starts at 1 only with b-11 = 3.
TEST(Vf66bSetAndIo, NetCtrlAtPowerUpIsNetworkOnlyWithB11_3_Section13_4_14) {
  for (unsigned b11 = 0; b11 <= 3; ++b11) {
    SCOPED_TRACE(testing::Message() << "b-11 = " << b11);
    auto c = acdrive::test::net_config(0, 0);  // output 20 carries no NetCtrl bit
    c.b11 = b11;
    Drive d(c);
    const Bytes want{static_cast<std::uint8_t>(b11 == 3)};
    EXPECT_EQ(d.get(0x29, 1, 5).data, want) << "NetCtrl";
    EXPECT_EQ(d.get(0x0F, 4, 1).data, want) << "Parameter 4 Network Control";
    EXPECT_EQ(d.get(0x29, 1, 15).data, want) << "CtrlFromNet";
  }
}

}  // namespace plc::sim

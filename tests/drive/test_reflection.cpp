// Every drive block and the axis reflect their fields for the debugger,
// trace and HMI (DESIGN.md "FB shape"); the axis' DevicePort is found by path.
#include <gtest/gtest.h>

#include <algorithm>

#include "plc/fb/drive/abs_encoder_init.hpp"
#include "plc/fb/drive/mc_blocks.hpp"
#include "plc/fb/drive/sina_para.hpp"
#include "plc/fb/drive/sina_pos.hpp"
#include "plc/fb/drive/sina_speed.hpp"
#include "plc/field_visitor.hpp"

namespace plc::drive {

struct Cell {
  DriveAxis axis1;
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
  SinaPos pos;
  SinaSpeed speed;
  SinaPara para;
  AbsEncoderInit abs;
  PLC_REFLECT(axis1, power, reset, mabs, mrel, mvel, home, stop, halt, rs, rp, pos, speed, para,
              abs)
};

TEST(Reflection, AllBlocksListTheirFields) {
  Cell c;
  const auto v = collect_fields("Cell", c);
  ASSERT_EQ(v.ports.size(), 1u);
  EXPECT_EQ(v.ports[0].path, "Cell.axis1.Port");
  auto has = [&](const std::string& p) {
    return std::any_of(v.fields.begin(), v.fields.end(),
                       [&](const auto& f) { return f.path == p; });
  };
  EXPECT_TRUE(has("Cell.axis1.ZSW1"));
  EXPECT_TRUE(has("Cell.axis1.State"));
  EXPECT_TRUE(has("Cell.pos.Status"));
  EXPECT_TRUE(has("Cell.pos.DiagID"));
  EXPECT_TRUE(has("Cell.mabs.CommandAborted"));
  EXPECT_TRUE(has("Cell.para.ValuesRead[63]"));
  EXPECT_TRUE(has("Cell.para.ErrorText"));
  EXPECT_TRUE(has("Cell.abs.Status"));
}

// Issue 10 point 5: every block's internal state (members ending in '_',
// and everything below them) is read-only for the debugger, the HMI and
// init:, and so is the state a block runs on (the axis' PLCopen State,
// AbsEncoderInit's Step) and the axis' RestartInhibit interlock (issue 9
// point 6, issue 21 point 2: no restart without an explicit MC_Reset or
// AckError); the rest of the interface stays writable, and SinaPara's Count
// (a length) behind its range check.
TEST(Reflection, InternalStateIsReadOnlyTheInterfaceWritable) {
  Cell c;
  const auto v = collect_fields("Cell", c);
  const FieldVisitor::Field* count = nullptr;
  for (const auto& f : v.fields) {
    const std::string& p = f.path;
    const bool internal = p.ends_with('_') || p.find("_.") != std::string::npos ||
                          p.find("_[") != std::string::npos || p == "Cell.axis1.State" ||
                          p == "Cell.axis1.RestartInhibit" || p == "Cell.abs.Step";
    EXPECT_EQ(f.access.read_only, internal) << p;
    if (p == "Cell.para.Count") count = &f;
  }
  ASSERT_NE(count, nullptr);
  ASSERT_TRUE(static_cast<bool>(count->access.check));
  UINT n = 65;
  EXPECT_EQ(count->access.check(&n), "Count must be 0 .. 64");
  n = 64;
  EXPECT_EQ(count->access.check(&n), "");
}

TEST(Reflection, UnboundAxisIsOffline) {
  DriveAxis a;
  a.begin(ScanContext{});
  EXPECT_EQ(a.CommError, kErrOffline);
  EXPECT_EQ(a.State, AxisState::ErrorStop);
}

}  // namespace plc::drive

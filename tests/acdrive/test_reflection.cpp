// The AC drive blocks reflect their fields for the debugger, trace and HMI
// (DESIGN.md "FB shape"); the drive's DevicePort is found by path, and the
// blocks' own state is read-only.
#include <gtest/gtest.h>

#include <algorithm>

#include "plc/fb/acdrive/ac_drive.hpp"
#include "plc/fb/acdrive/ac_drive_attribute.hpp"
#include "plc/field_visitor.hpp"

namespace plc::acdrive {

struct Cell {
  AcDrive conveyor;
  AcDriveAttribute attr;
  PLC_REFLECT(conveyor, attr)
};

TEST(AcdriveReflection, BlocksListTheirFieldsAndPort) {
  Cell c;
  const auto v = collect_fields("Cell", c);
  ASSERT_EQ(v.ports.size(), 1u);
  EXPECT_EQ(v.ports[0].path, "Cell.conveyor.Port");
  auto find = [&](const std::string& p) {
    return std::find_if(v.fields.begin(), v.fields.end(),
                        [&](const auto& f) { return f.path == p; });
  };
  for (const char* p : {"Cell.conveyor.SpeedRef", "Cell.conveyor.State", "Cell.conveyor.FaultBits",
                        "Cell.conveyor.FaultText", "Cell.conveyor.Monitor[2]",
                        "Cell.attr.ValueRead", "Cell.attr.Data[31]", "Cell.attr.GeneralStatus"})
    EXPECT_NE(find(p), v.fields.end()) << p;
  // RestartInhibit is the no-restart interlock: the debugger cannot clear it.
  for (const char* p :
       {"Cell.conveyor.RestartInhibit", "Cell.conveyor.reset_phase_", "Cell.attr.prev_execute_"}) {
    const auto it = find(p);
    ASSERT_NE(it, v.fields.end()) << p;
    EXPECT_TRUE(it->access.read_only) << p;
  }
  const auto cmd = find("Cell.conveyor.RunFwd");
  ASSERT_NE(cmd, v.fields.end());
  EXPECT_FALSE(cmd->access.read_only);
}

}  // namespace plc::acdrive

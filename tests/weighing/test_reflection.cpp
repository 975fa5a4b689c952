// Every weighing block names its fields for reflection (debugger, HMI,
// trace, recording snapshots), internal state included.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <type_traits>

#include "plc/fb/weighing/batch_weigh.hpp"
#include "plc/fb/weighing/command.hpp"
#include "plc/fb/weighing/digital_outputs.hpp"
#include "plc/fb/weighing/read_value.hpp"
#include "plc/fb/weighing/status.hpp"
#include "plc/fb/weighing/string_value.hpp"
#include "plc/fb/weighing/write_value.hpp"
#include "plc/field_visitor.hpp"

namespace wg = plc::weighing;

namespace {

// Walks the block with the runtime's own FieldVisitor (what the variable
// registry, the debugger and recordings use): every field must be of a
// reflectable kind (it would not compile otherwise) and every path unique.
template <class FB>
int fields() {
  FB fb;
  const plc::FieldVisitor v = plc::collect_fields("fb", fb);
  std::set<std::string> names;
  for (const auto& f : v.fields) names.insert(f.path);
  for (const auto& p : v.ports) names.insert(p.path);
  EXPECT_EQ(names.size(), v.fields.size() + v.ports.size()) << "duplicate field name";
  return static_cast<int>(names.size());
}

}  // namespace

TEST(WeighingReflection, AllBlocksReflectTheirFields) {
  // 22 interface fields + 29 scalars and 9 per-client arrays of arbitration state.
  EXPECT_EQ(22 + 29 + 9 * wg::PR5510_Device::kMaxClients, fields<wg::PR5510_Device>());
  EXPECT_EQ(10 + 2, fields<wg::PR5510_ReadValue>());  // + slot, last code
  EXPECT_EQ(9 + 2, fields<wg::PR5510_WriteValue>());  // + slot, Execute memory
  EXPECT_EQ(6 + 2, fields<wg::PR5510_Command>());
  EXPECT_EQ(8, fields<wg::PR5510_DigitalOutputs>());
  EXPECT_EQ(25, fields<wg::PR5510_Status>());  // Valid + the 24 bits of §3.4
  EXPECT_EQ(7 + 3 + wg::kStringLength, fields<wg::PR5510_ReadString>());  // + chunk buffer
  EXPECT_EQ(7 + 4, fields<wg::PR5510_WriteString>());
  EXPECT_GT(fields<wg::PR5510_BatchWeigh>(), 40);
}

namespace {

// Issue 10 point 5: the block's internal state (members ending in '_', and
// everything below them) and the state it runs on (`extra`) are read-only
// for the debugger, the HMI and init:; the rest of the interface writable.
template <class FB>
void expect_internal_read_only(std::set<std::string> extra = {}) {
  FB fb;
  const plc::FieldVisitor v = plc::collect_fields("fb", fb);
  for (const auto& f : v.fields) {
    const std::string& p = f.path;
    const bool internal = p.ends_with('_') || p.find("_.") != std::string::npos ||
                          p.find("_[") != std::string::npos || extra.count(p) != 0;
    EXPECT_EQ(f.access.read_only, internal) << p;
  }
}

}  // namespace

TEST(WeighingReflection, InternalStateIsReadOnlyTheInterfaceWritable) {
  expect_internal_read_only<wg::PR5510_Device>({"fb.ReadHolder"});
  expect_internal_read_only<wg::PR5510_ReadValue>();
  expect_internal_read_only<wg::PR5510_WriteValue>();
  expect_internal_read_only<wg::PR5510_Command>();
  expect_internal_read_only<wg::PR5510_DigitalOutputs>();
  expect_internal_read_only<wg::PR5510_Status>();
  expect_internal_read_only<wg::PR5510_ReadString>();
  expect_internal_read_only<wg::PR5510_WriteString>();
  expect_internal_read_only<wg::PR5510_BatchWeigh>({"fb.State"});
}

// The debugger's typed entries for a front end in another process (issue 22,
// "Process isolation": the HMI bridge parses literals and conditions in its
// own process and hands plcrun bytes and code, never text): write_raw and
// force_raw apply the same checks as the text path, a breakpoint given as
// code is validated, bound, listed from its code and survives a rebuild
// without its text being parsed, read_typed gives what read() formats.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "plc/debug/debugger.hpp"
#include "plc/iec_literal.hpp"
#include "test_helpers.hpp"
#include "test_programs.hpp"

using namespace plc;
using plc::debug::ConditionCode;
using plc::debug::ConditionOperand;
using plc::debug::Debugger;

namespace {

using Op = ConditionCode::Op;

struct Session {
  CellConfig cfg;
  std::unique_ptr<Debugger> dbg;
  explicit Session(const std::string& yaml) {
    cfg = parse_cell_config(yaml, "typed.yaml");
    Debugger::Options o;
    o.span = std::chrono::minutes(1);
    dbg = std::make_unique<Debugger>([this] { return std::make_unique<Runtime>(cfg); }, o);
  }
  std::string value(const std::string& name) { return dbg->read({name}).front().text; }
};

const char* kShapes = R"(
cell: typed
tasks: [{name: main, period: 1ms, programs: [S, G]}]
programs: [{name: S, type: Shapes}, {name: G, type: Guarded}]
)";

template <class T>
Debugger::Reply write_raw(Debugger& d, const std::string& name, T v, bool force = false) {
  alignas(8) unsigned char b[8] = {};
  std::memcpy(b, &v, sizeof v);
  return force ? d.force_raw(name, b) : d.write_raw(name, b);
}

}  // namespace

TEST(DebuggerTyped, WriteRawTakesEffectAtTheNextScanLikeWrite) {
  Session s(kShapes);
  s.dbg->step(1);
  const auto r = write_raw(*s.dbg, "S.w", std::uint16_t(0x1234));
  EXPECT_TRUE(r.ok) << r.text;
  EXPECT_NE(r.text.find("will write S.w := 16#1234"), std::string::npos) << r.text;
  EXPECT_EQ(s.value("S.w"), "16#047F");  // not before the next scan
  s.dbg->step(1);
  EXPECT_EQ(s.value("S.w"), "16#1234");
}

// What the text path refuses, the bytes path refuses with the same words:
// a block's read-only state, a STRING, a value the block's write check
// refuses; and what text cannot even express: a BOOL byte other than 0/1,
// a NaN or infinite REAL. Nothing is applied.
TEST(DebuggerTyped, RawValuesGetTheTextPathsChecks) {
  Session s(kShapes);
  s.dbg->step(1);
  const std::string before = s.value("S.x");
  struct Row {
    Debugger::Reply r;
    const char* why;
  };
  const Row rows[] = {
      {write_raw(*s.dbg, "G.log.head_", std::uint8_t(3)), "read-only"},
      {write_raw(*s.dbg, "S.name", std::uint64_t(0)), "STRING"},
      {write_raw(*s.dbg, "G.log.Depth", std::int16_t(9)), "Depth must be 1 .. 8"},
      {write_raw(*s.dbg, "G.log.In", std::uint8_t(2)), "not a BOOL"},
      {write_raw(*s.dbg, "S.x", std::numeric_limits<double>::quiet_NaN()), "not a number"},
      {write_raw(*s.dbg, "S.x", std::numeric_limits<double>::infinity(), true), "infinity"},
      {write_raw(*s.dbg, "Nope.x", std::uint8_t(1)), "unknown variable"},
  };
  for (const Row& row : rows) {
    EXPECT_FALSE(row.r.ok) << row.why;
    EXPECT_NE(row.r.text.find(row.why), std::string::npos) << row.r.text;
  }
  // The same refusal as the text path's, word for word.
  EXPECT_EQ(rows[2].r.text, s.dbg->write("G.log.Depth", "9").text);
  s.dbg->step(2);
  EXPECT_EQ(s.value("S.x"), before);
  EXPECT_EQ(s.dbg->execute("forces"), "no forces\n");
}

TEST(DebuggerTyped, ForceRawForcesAndForcedListsIt) {
  Session s(kShapes);
  s.dbg->step(1);
  EXPECT_TRUE(write_raw(*s.dbg, "S.arr[1]", std::int16_t(-7), true).ok);
  s.dbg->step(3);
  EXPECT_EQ(s.value("S.arr[1]"), "-7");
  EXPECT_EQ(s.dbg->forced(), std::vector<std::string>{"S.arr[1]"});
  EXPECT_TRUE(s.dbg->unforce("S.arr[1]", true).ok);
  EXPECT_TRUE(s.dbg->forced().empty());
}

TEST(DebuggerTyped, ReadTypedGivesWhatReadFormats) {
  Session s(kShapes);
  s.dbg->step(1);
  const auto t = s.dbg->read_typed({"S.x", "S.w", "S.name", "Nope"});
  ASSERT_EQ(t.size(), 4U);
  double x = 0;
  std::memcpy(&x, t[0].bytes, sizeof x);
  EXPECT_EQ(x, 1.5);
  EXPECT_EQ(t[1].type, VarType::WORD);
  EXPECT_EQ(format_value(VarType::STRING, t[2].bytes), "'cell'");
  EXPECT_NE(t[3].error.find("unknown variable"), std::string::npos);
  const auto r = s.dbg->read({"S.x", "S.w", "S.name", "Nope"});
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(r[i].text, format_value(t[i].type, t[i].bytes));
}

// A breakpoint as code: validated and bound, listed with the text made from
// the code, hit like a typed one; after goto (a rebuilt runtime) it is
// bound again by path, not parsed.
TEST(DebuggerTyped, BreakpointFromCodeHitsAndSurvivesARebuild) {
  Session s(kShapes);
  // G.scans = 5
  ConditionCode c;
  c.consts = {{false, 5, 0}};
  c.code = {{Op::Var, 0}, {Op::Const, 0}, {Op::Eq, 0}};
  auto r = s.dbg->add_breakpoint(c, {ConditionOperand{"G.scans", {}}});
  ASSERT_TRUE(r.ok) << r.text;
  EXPECT_EQ(r.text, "breakpoint 1: G.scans = 5\n");
  EXPECT_NE(s.dbg->execute("continue").find("breakpoint 1 (G.scans = 5) hit"), std::string::npos);
  EXPECT_EQ(s.value("G.scans"), "5");
  EXPECT_NE(s.dbg->execute("goto 0").find("scan 0"), std::string::npos);
  EXPECT_NE(s.dbg->execute("continue").find("breakpoint 1 (G.scans = 5) hit"), std::string::npos);
}

TEST(DebuggerTyped, BreakpointCodeThatDoesNotValidateOrBindIsRefused) {
  Session s(kShapes);
  struct Row {
    ConditionCode code;
    std::vector<ConditionOperand> ops;
    const char* why;
  };
  ConditionCode eq;
  eq.consts = {{false, 1, 0}};
  eq.code = {{Op::Var, 0}, {Op::Const, 0}, {Op::Eq, 0}};
  ConditionCode underflow = eq;
  underflow.code = {{Op::Eq, 0}};
  ConditionCode bad_op = eq;
  bad_op.code[2].op = Op(200);
  const Row rows[] = {
      {eq, {}, "operand index out of range"},
      {underflow, {}, "without its two operands"},
      {bad_op, {ConditionOperand{"G.scans", {}}}, "unknown op code"},
      {eq, {ConditionOperand{"Nope.x", {}}}, "unknown variable 'Nope.x'"},
      {eq, {ConditionOperand{"S.name", {}}}, "STRING"},
      {eq,
       {ConditionOperand{"", io::IecAddress{io::Area::Output, io::AddrSize::Word, 1'000'000, 0}}},
       "outside the image"},
  };
  for (const Row& row : rows) {
    const auto r = s.dbg->add_breakpoint(row.code, row.ops);
    EXPECT_FALSE(r.ok) << row.why;
    EXPECT_NE(r.text.find(row.why), std::string::npos) << r.text;
  }
  EXPECT_EQ(s.dbg->execute("breaks"), "no breakpoints\n");
}

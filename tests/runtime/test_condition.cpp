// Breakpoint and trigger conditions: ST operators, precedence, literals,
// variables and addresses.
#include <gtest/gtest.h>

#include "plc/debug/condition.hpp"
#include "test_helpers.hpp"
#include "test_programs.hpp"

using namespace plc;
using plc::debug::Condition;

namespace {

struct Fixture {
  std::unique_ptr<Runtime> rt = plctest::make_runtime(R"(
tasks: [{name: main, period: 1ms, programs: [S, W]}]
programs: [{name: S, type: Shapes}, {name: W, type: Spinner}]
)");
  std::optional<Condition> compile(const std::string& text, std::string& err) {
    return Condition::compile(text, rt->vars(), rt->image(), rt->byte_order(), err);
  }
  bool eval(const std::string& text) {
    std::string err;
    auto c = compile(text, err);
    EXPECT_TRUE(c) << text << ": " << err;
    return c && c->holds();
  }
};

}  // namespace

TEST(Condition, ComparesVariablesOfEveryKindWithLiterals) {
  Fixture f;
  // Shapes: mode = 3 (SINT enum), w = 16#047F, x = 1.5, arr = {1, 2, 3}
  EXPECT_TRUE(f.eval("S.mode = 3"));
  EXPECT_TRUE(f.eval("S.w = 16#047F"));
  EXPECT_TRUE(f.eval("S.w = 1151"));
  EXPECT_TRUE(f.eval("S.x > 1.25 AND S.x < 2"));
  EXPECT_TRUE(f.eval("S.arr[2] - S.arr[0] = 2"));
  EXPECT_TRUE(f.eval("S.inner.timers[0].PT = T#0s"));
  EXPECT_TRUE(f.eval("NOT S.inner.edge.Q"));
  EXPECT_FALSE(f.eval("S.mode <> 3"));
  EXPECT_TRUE(f.eval("W.spin_us >= 50000"));
}

TEST(Condition, PrecedenceAndOperators) {
  Fixture f;
  EXPECT_TRUE(f.eval("1 + 2 * 3 = 7"));
  EXPECT_TRUE(f.eval("(1 + 2) * 3 = 9"));
  EXPECT_TRUE(f.eval("TRUE OR FALSE AND FALSE")) << "AND binds tighter than OR";
  EXPECT_TRUE(f.eval("TRUE XOR FALSE"));
  EXPECT_FALSE(f.eval("TRUE XOR TRUE"));
  EXPECT_TRUE(f.eval("7 MOD 4 = 3"));
  EXPECT_TRUE(f.eval("-3 < -2"));
  EXPECT_TRUE(f.eval("NOT 1 = 2"));
  EXPECT_TRUE(f.eval("10 / 0 = 0")) << "division by zero yields 0, never traps";
  EXPECT_TRUE(f.eval("TRUE & TRUE"));
  EXPECT_TRUE(f.eval("T#1s = 1000000000"));
}

TEST(Condition, ReadsImageAddressesAndLocatedVariables) {
  Fixture f;
  f.rt->image().area(io::Area::Output)[0] = 0x12;
  f.rt->image().area(io::Area::Output)[1] = 0x34;
  EXPECT_TRUE(f.eval("%QW0 = 16#1234"));
  EXPECT_TRUE(f.eval("%QX0.4 AND NOT %QX0.0"));
  EXPECT_TRUE(f.eval("%QB1 = 16#34"));
}

TEST(Condition, ReportsErrorsWithTheirCause) {
  Fixture f;
  struct Row {
    const char* text;
    const char* error;
  };
  const Row rows[] = {
      {"S.nope = 1", "unknown variable 'S.nope'"},
      {"S.mode =", "incomplete condition"},
      {"(S.mode = 3", "missing ')'"},
      {"S.mode = 3)", "unexpected ')'"},
      {"S.name = 1", "is a STRING"},
      {"%QX0.9", "out of range 0..7"},
      {"S.mode = 3 3", "unexpected '3'"},
      {"T#xyz > 1", "not a duration"},
  };
  for (const Row& r : rows) {
    std::string err;
    EXPECT_FALSE(f.compile(r.text, err)) << r.text;
    EXPECT_NE(err.find(r.error), std::string::npos) << r.text << " -> " << err;
  }
}

TEST(Condition, KnowsTheTaskOfItsFirstVariable) {
  Fixture f;
  std::string err;
  EXPECT_EQ(f.compile("S.mode = 3", err)->task(), 0);
  EXPECT_EQ(f.compile("%QX0.0", err)->task(), -1);
}

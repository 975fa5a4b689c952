// Breakpoint and trigger conditions: ST operators, precedence, literals,
// variables and addresses.
#include <gtest/gtest.h>

#include <functional>

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

// Issue 10 point 6: integer arithmetic is LINT that wraps around (header of
// condition.hpp), never a trap or undefined behaviour. (-2^63) / -1 used to
// raise SIGFPE; the other rows were signed overflow.
TEST(Condition, IntegerArithmeticWrapsAroundLikeLint) {
  Fixture f;
  const std::string min = "(-9223372036854775807 - 1)";
  EXPECT_TRUE(f.eval(min + " / -1 = " + min));
  EXPECT_TRUE(f.eval(min + " MOD -1 = 0"));
  EXPECT_TRUE(f.eval("-" + min + " = " + min));
  EXPECT_TRUE(f.eval("9223372036854775807 + 1 = " + min));
  EXPECT_TRUE(f.eval(min + " - 1 = 9223372036854775807"));
  EXPECT_TRUE(f.eval("9223372036854775807 * 2 = -2"));
  EXPECT_TRUE(f.eval(min + " * -1 = " + min));
  EXPECT_TRUE(f.eval("-7 / 2 = -3 AND -7 MOD 2 = -1")) << "IEC: truncating division";
}

TEST(Condition, DivisionAndModByZeroGiveZero) {
  Fixture f;
  EXPECT_TRUE(f.eval("10 / 0 = 0"));
  EXPECT_TRUE(f.eval("10 MOD 0 = 0"));
  EXPECT_TRUE(f.eval("S.x / 0 = 0"));
  EXPECT_TRUE(f.eval("S.x MOD 0.0 = 0"));
  EXPECT_FALSE(f.eval("S.w / (S.mode - 3) > 1")) << "false while the divisor is 0";
}

// REAL follows IEEE 754: overflow is inf, inf - inf is NaN, and NaN is
// unordered. The old comparison called NaN equal to everything.
TEST(Condition, RealNanComparesUnordered) {
  Fixture f;
  const std::string nan = "(1.0E308 * 10 - 1.0E308 * 10)";
  EXPECT_FALSE(f.eval(nan + " = 0"));
  EXPECT_FALSE(f.eval(nan + " = " + nan));
  EXPECT_FALSE(f.eval(nan + " < 1 OR " + nan + " >= 1 OR " + nan + " <= 1 OR " + nan + " > 1"));
  EXPECT_TRUE(f.eval(nan + " <> 0"));
  EXPECT_TRUE(f.eval("1.0E308 * 10 > 9223372036854775807")) << "+inf above every LINT";
  EXPECT_TRUE(f.eval("-1.0E308 * 10 < -9223372036854775807 - 1"));
}

// Integers meet reals exactly; converting the integer to double rounds
// above 2^53 (2^53 + 1 -> 2^53, 2^63 - 1 -> 2^63).
TEST(Condition, IntegerAgainstRealComparesExactly) {
  Fixture f;
  EXPECT_TRUE(f.eval("9007199254740993 > 9007199254740992.0"));
  EXPECT_TRUE(f.eval("9007199254740992.0 < 9007199254740993"));
  EXPECT_TRUE(f.eval("9223372036854775807 < 9223372036854775808.0"));
  EXPECT_FALSE(f.eval("9223372036854775807 = 9223372036854775808.0"));
  EXPECT_TRUE(f.eval("-9223372036854775807 - 1 = -9223372036854775808.0"));
  EXPECT_TRUE(f.eval("2 > 1.5 AND 1 < 1.5 AND -2 < -1.5 AND 3 = 3.0 AND 3 <= 3.0"));
  EXPECT_TRUE(f.eval("S.x > 1 AND 2 > S.x")) << "S.x = 1.5";
}

// Issue 10 point 6: nesting is limited while parsing (each '(' / NOT / '-'
// recursed; 5,000 parentheses or 200,000 NOT overflowed the stack).
TEST(Condition, NestingBeyondTheLimitIsRefusedNamingTheColumn) {
  Fixture f;
  const int lim = Condition::kMaxNesting;
  auto parens = [](int n) { return std::string(n, '(') + "1" + std::string(n, ')') + " = 1"; };
  EXPECT_TRUE(f.eval(parens(lim)));
  struct Row {
    std::string text;
    std::size_t column;  // of the token that opens level kMaxNesting + 1
  };
  std::string nots;
  for (int i = 0; i < 200000; ++i) nots += "NOT ";
  std::string minus;
  for (int i = 0; i < 200000; ++i) minus += "- ";
  const Row rows[] = {
      {parens(5000), std::size_t(lim) + 1},
      {nots + "TRUE", std::size_t(lim) * 4 + 1},
      {"1 = " + minus + "1", 4 + std::size_t(lim) * 2 + 1},
      {"NOT (-(NOT " + parens(lim) + "))", 0},
  };
  for (const Row& r : rows) {
    std::string err;
    EXPECT_FALSE(f.compile(r.text, err)) << r.text.substr(0, 40);
    EXPECT_NE(err.find("nested too deeply"), std::string::npos) << err;
    if (r.column) {
      EXPECT_NE(err.find("at column " + std::to_string(r.column) + " "), std::string::npos) << err;
    }
  }
}

// Issue 22: the compiler runs against a resolver instead of the runtime's
// registry (the HMI bridge's process compiles against a cell description),
// and the code it makes reads back to text that compiles to the same code.
TEST(ConditionCode, CompilesAgainstAResolverAndReadsBackAsTheSameCode) {
  std::vector<std::string> names;
  const debug::ConditionResolver resolve =
      [&names](const std::string& n, std::string& why) -> std::optional<std::uint16_t> {
    if (n == "Nope") {
      why = "unknown variable 'Nope'";
      return std::nullopt;
    }
    names.push_back(n);
    return std::uint16_t(names.size() - 1);
  };
  const char* texts[] = {
      "Tank.step = 3",
      "NOT Tank.enable OR (Tank.level >= 16#5000 AND Tank.hold.ET > T#1s)",
      "%IX0.3 AND %QW0 <> 0",
      "a - (b - c) = a - b - c",
      "-(a + 1) * 2 > 1.5 XOR NOT NOT b",
      "(a = 1) = (b = 2)",
      "x > T#-20ms AND y < INT#-5 AND z = 9223372036854775808.0 AND w < 0.1",
  };
  for (const char* text : texts) {
    names.clear();
    std::string err;
    const auto code = debug::compile_condition(text, resolve, err);
    ASSERT_TRUE(code) << text << ": " << err;
    EXPECT_EQ(debug::validate(*code, names.size()), "") << text;
    const auto saved = names;
    const std::string back = debug::to_text(*code, [&saved](std::uint16_t i) { return saved[i]; });
    names.clear();
    const auto again = debug::compile_condition(back, resolve, err);
    ASSERT_TRUE(again) << back << ": " << err;
    EXPECT_EQ(*again, *code) << text << " -> " << back;
    EXPECT_EQ(names, saved) << back;
  }
  std::string err;
  EXPECT_FALSE(debug::compile_condition("Nope > 1", resolve, err));
  EXPECT_EQ(err, "unknown variable 'Nope'");
}

// Code from another process is checked before anything evaluates it.
TEST(ConditionCode, ValidateRefusesEveryMalformedCode) {
  using Op = debug::ConditionCode::Op;
  debug::ConditionCode ok;
  ok.consts = {{false, 1, 0}};
  ok.code = {{Op::Var, 0}, {Op::Const, 0}, {Op::Add, 0}, {Op::Neg, 0}};
  EXPECT_EQ(debug::validate(ok, 1), "");
  struct Row {
    std::function<void(debug::ConditionCode&)> change;
    std::size_t operands;
    const char* why;
  };
  const Row rows[] = {
      {[](auto& c) { c.code.clear(); }, 1, "empty code"},
      {[](auto& c) {
         c.code.resize(257, {Op::Const, 0});
       },
       1, "257 instructions"},
      {[](auto& c) { c.consts.resize(65); }, 1, "65 constants"},
      {[](auto&) {}, 65, "65 operands"},
      {[](auto& c) { c.code[1].op = Op(18); }, 1, "unknown op code 18 at instruction 1"},
      {[](auto& c) { c.code[1].index = 1; }, 1, "constant index out of range"},
      {[](auto&) {}, 0, "operand index out of range at instruction 0"},
      {[](auto& c) {
         c.code.insert(c.code.begin(), {Op::Not, 0});
       },
       1, "without its operand"},
      {[](auto& c) { c.code.erase(c.code.begin()); }, 1, "without its two operands"},
      {[](auto& c) {
         c.code.push_back({Op::Const, 0});
       },
       1, "2 values left"},
      {[](auto& c) {
         c.code.assign(33, {Op::Const, 0});
       },
       1, "more than 32 operands pending"},
  };
  for (const Row& r : rows) {
    debug::ConditionCode c = ok;
    r.change(c);
    const std::string why = debug::validate(c, r.operands);
    EXPECT_NE(why.find(r.why), std::string::npos) << r.why << ": " << why;
  }
}

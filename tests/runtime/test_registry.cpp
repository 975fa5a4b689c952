// The variable registry: every program variable and FB field by path, with
// type and address; reading and writing through it.
#include <gtest/gtest.h>

#include "plc/field_visitor.hpp"
#include "test_helpers.hpp"
#include "test_programs.hpp"

using namespace plc;

namespace {
const char* kCell = R"(
tasks:
  - {name: main, period: 1ms, programs: [S, W]}
programs:
  - {name: S, type: Shapes}
  - name: W
    type: Spinner
    bind: {out: "%QW2"}
    init: {spin_us: 7}
)";
}

TEST(Registry, NamesNestedFieldsArraysEnumsAndLocatedVariables) {
  auto rt = plctest::make_runtime(kCell);
  const auto& v = rt->vars();
  struct Row {
    const char* path;
    VarType type;
    const char* value;
  };
  const Row rows[] = {
      {"S.inner.edge.CLK", VarType::BOOL, "FALSE"},
      {"S.inner.timers[1].PT", VarType::TIME, "T#0s"},
      {"S.mode", VarType::SINT, "3"},
      {"S.w", VarType::WORD, "16#047F"},
      {"S.name", VarType::STRING, "'cell'"},
      {"S.x", VarType::LREAL, "1.5"},
      {"S.arr[2]", VarType::INT, "3"},
      {"W.spin_us", VarType::DINT, "7"},
  };
  for (const Row& r : rows) {
    const VarInfo* vi = v.find(r.path);
    ASSERT_NE(vi, nullptr) << r.path;
    EXPECT_EQ(vi->type, r.type) << r.path;
    EXPECT_EQ(VarRegistry::format(*vi), r.value) << r.path;
  }
  const VarInfo* out = v.find("W.out");
  ASSERT_NE(out, nullptr);
  ASSERT_TRUE(out->address);
  EXPECT_EQ(out->address->to_string(), "%QW2") << "bind: moves the address";
  EXPECT_EQ(v.find("S.nothing"), nullptr);
}

TEST(Registry, WritesReachTheProgramAndTheImage) {
  auto rt = plctest::make_runtime(kCell);
  auto* s = static_cast<plctest::Shapes*>(rt->program("S"));
  EXPECT_EQ(VarRegistry::write_text(*rt->vars().find("S.arr[0]"), "-9"), "");
  EXPECT_EQ(s->arr[0], -9);
  EXPECT_EQ(VarRegistry::write_text(*rt->vars().find("S.name"), "'tank'"), "");
  EXPECT_EQ(s->name.view(), "tank");
  EXPECT_NE(VarRegistry::write_text(*rt->vars().find("S.arr[0]"), "abc"), "");
  auto* w = static_cast<plctest::Spinner*>(rt->program("W"));
  EXPECT_EQ(VarRegistry::write_text(*rt->vars().find("W.out"), "16#0102"), "");
  EXPECT_EQ(w->out.get(), 0x0102);
}

TEST(Registry, CollectFieldsWorksOnAnyReflectedObject) {
  plctest::Shapes::Inner inner;
  auto f = collect_fields("x", inner);
  ASSERT_EQ(f.fields.size(), 3u + 2u * 6u);
  EXPECT_EQ(f.fields[0].path, "x.edge.CLK");
}

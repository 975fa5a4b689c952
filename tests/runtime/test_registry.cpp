// The variable registry: every program variable and FB field by path, with
// type and address; reading and writing through it.
#include <gtest/gtest.h>

#include <map>

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

// Issue 10 point 5: the write policy of reflect.hpp. Internal state is
// readable but refused for writes from outside, whatever the value;
// everything below an internal field is internal too; a write check lets a
// field through only with a value its block accepts.
TEST(RegistryWritePolicy, InternalStateIsReadOnlyAndWriteChecksVetValues) {
  auto rt = plctest::make_runtime(R"(
tasks: [{name: main, period: 1ms, programs: [G]}]
programs: [{name: G, type: Guarded}]
)");
  const auto& v = rt->vars();
  auto* g = static_cast<plctest::Guarded*>(rt->program("G"));
  for (const char* p : {"G.log.head_", "G.log.buf_[7]", "G.log.edge_.CLK", "G.log.edge_.M"}) {
    const VarInfo* vi = v.find(p);
    ASSERT_NE(vi, nullptr) << p;
    EXPECT_TRUE(vi->read_only) << p;
    EXPECT_EQ(
        VarRegistry::format(*vi),
        p == std::string("G.log.edge_.CLK") || p == std::string("G.log.edge_.M") ? "FALSE" : "0")
        << "readable: " << p;
    const std::string err = VarRegistry::write_text(*vi, "200");
    EXPECT_NE(err.find("read-only: internal state of its function block"), std::string::npos)
        << p << ": " << err;
  }
  EXPECT_EQ(g->log.head_, 0) << "a refused write changes nothing";
  for (const char* p : {"G.log.In", "G.log.Depth", "G.log.scale_", "G.scans"})
    EXPECT_FALSE(v.find(p)->read_only) << p;

  const VarInfo& scale = *v.find("G.log.scale_");
  EXPECT_EQ(VarRegistry::write_text(scale, "0"),
            "refused by its function block: scale_ must be 1 .. 1000");
  EXPECT_EQ(g->log.scale_, 1);
  EXPECT_EQ(VarRegistry::write_text(scale, "250"), "");
  EXPECT_EQ(g->log.scale_, 250);
  const VarInfo& depth = *v.find("G.log.Depth");
  EXPECT_EQ(VarRegistry::write_text(depth, "9"),
            "refused by its function block: Depth must be 1 .. 8");
  EXPECT_EQ(VarRegistry::write_text(depth, "3"), "");
  EXPECT_EQ(g->log.Depth, 3);
  // The runtime's own restores (recording snapshots) write directly.
  const USINT head = 5;
  VarRegistry::write(*v.find("G.log.head_"), &head);
  EXPECT_EQ(g->log.head_, 5);
}

// A visitor sees the attributes; a two-argument visitor still works.
TEST(RegistryWritePolicy, FieldVisitorCarriesAttributesAndInheritsInternal) {
  plctest::RingLog log;
  auto f = collect_fields("x", log);
  std::map<std::string, const FieldVisitor::Field*> by_path;
  for (const auto& fld : f.fields) by_path[fld.path] = &fld;
  EXPECT_FALSE(by_path.at("x.In")->access.read_only);
  EXPECT_FALSE(by_path.at("x.Depth")->access.read_only);
  EXPECT_TRUE(static_cast<bool>(by_path.at("x.Depth")->access.check));
  EXPECT_TRUE(by_path.at("x.head_")->access.read_only);
  EXPECT_TRUE(by_path.at("x.buf_[0]")->access.read_only);
  EXPECT_FALSE(by_path.at("x.scale_")->access.read_only) << "internal, but its block checks it";
  EXPECT_TRUE(by_path.at("x.edge_.CLK")->access.read_only) << "below an internal field";
  EXPECT_FALSE(static_cast<bool>(by_path.at("x.edge_.CLK")->access.check));
}

namespace {

// The ConfigError of a Guarded program with this init: (none: empty message).
ConfigError init_error(const std::string& init) {
  try {
    plctest::make_runtime(R"(
tasks: [{name: main, period: 1ms, programs: [G]}]
programs:
  - name: G
    type: Guarded
    init: {)" + init + "}\n");
  } catch (const ConfigError& e) {
    return e;
  }
  return ConfigError("", {}, "");
}

}  // namespace

// init: of a read-only variable is a config error at the key (file:line:
// column, plcrun exits 2: test_config_errors.cpp runs it through plcrun).
TEST(RegistryWritePolicy, InitOfInternalStateIsAConfigErrorAtTheKey) {
  const ConfigError e = init_error("log.head_: 3");
  EXPECT_EQ(e.mark.line, 6);
  EXPECT_EQ(e.mark.column, 12);
  EXPECT_NE(e.message.find("'log.head_'"), std::string::npos) << e.what();
  EXPECT_NE(e.message.find("read-only"), std::string::npos) << e.what();
  // A checked field: the check's reason, at the value.
  const ConfigError c = init_error("log.scale_: 5000");
  EXPECT_EQ(c.mark.line, 6);
  EXPECT_EQ(c.mark.column, 24);
  EXPECT_NE(c.message.find("scale_ must be 1 .. 1000"), std::string::npos) << c.what();
  EXPECT_EQ(init_error("log.scale_: 500").message, "") << "within the check: accepted";
}

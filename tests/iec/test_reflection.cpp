// Every IEC FB reflects its IEC-named inputs/outputs and its internal state
// (DESIGN.md: the debugger shows internal state), and is a plain inline
// struct: no virtual calls, trivially copyable, no heap.
#include <gtest/gtest.h>

#include <string>
#include <type_traits>
#include <vector>

#include "plc/fb/iec/iec.hpp"

namespace {

using namespace std::chrono_literals;

struct NameCollector {
  std::vector<std::string> names;
  template <class T>
  void operator()(const char* name, T&) {
    static_assert(plc::is_elementary_v<T>, "IEC FBs reflect only elementary fields");
    names.emplace_back(name);
  }
};

template <class Fb>
std::vector<std::string> names_of() {
  Fb fb;
  NameCollector c;
  fb.reflect(c);
  return c.names;
}

using Names = std::vector<std::string>;

TEST(IecReflection, FieldsInIecOrderWithInternalState) {
  EXPECT_EQ(names_of<plc::iec::TON>(), (Names{"IN", "PT", "Q", "ET", "start_", "running_"}));
  EXPECT_EQ(names_of<plc::iec::TOF>(), (Names{"IN", "PT", "Q", "ET", "start_", "prev_in_"}));
  EXPECT_EQ(names_of<plc::iec::TP>(), (Names{"IN", "PT", "Q", "ET", "start_", "prev_in_"}));
  EXPECT_EQ(names_of<plc::iec::R_TRIG>(), (Names{"CLK", "Q", "M"}));
  EXPECT_EQ(names_of<plc::iec::F_TRIG>(), (Names{"CLK", "Q", "M"}));
  EXPECT_EQ(names_of<plc::iec::CTU>(), (Names{"CU", "R", "PV", "Q", "CV", "cu_prev_"}));
  EXPECT_EQ(names_of<plc::iec::CTD>(), (Names{"CD", "LD", "PV", "Q", "CV", "cd_prev_"}));
  EXPECT_EQ(names_of<plc::iec::CTUD>(),
            (Names{"CU", "CD", "R", "LD", "PV", "QU", "QD", "CV", "cu_prev_", "cd_prev_"}));
  EXPECT_EQ(names_of<plc::iec::SR>(), (Names{"S1", "R", "Q1"}));
  EXPECT_EQ(names_of<plc::iec::RS>(), (Names{"S", "R1", "Q1"}));
}

// Issue 10 point 5: internal state (the edge memories, the timers' start)
// is read-only for the debugger, the HMI and init:; the IEC inputs and
// outputs stay writable.
struct InternalCollector {
  std::vector<std::string> names;
  template <class T>
  void operator()(const char* name, T&, const plc::FieldMeta& meta) {
    if (meta.internal && !meta.check) names.push_back(std::string("x.") + name);
  }
};

template <class Fb>
std::vector<std::string> read_only_of() {
  Fb fb;
  InternalCollector c;
  fb.reflect(c);
  return c.names;
}

TEST(IecReflection, InternalStateIsReadOnly) {
  EXPECT_EQ(read_only_of<plc::iec::TON>(), (Names{"x.start_", "x.running_"}));
  EXPECT_EQ(read_only_of<plc::iec::TOF>(), (Names{"x.start_", "x.prev_in_"}));
  EXPECT_EQ(read_only_of<plc::iec::TP>(), (Names{"x.start_", "x.prev_in_"}));
  EXPECT_EQ(read_only_of<plc::iec::R_TRIG>(), (Names{"x.M"}));
  EXPECT_EQ(read_only_of<plc::iec::F_TRIG>(), (Names{"x.M"}));
  EXPECT_EQ(read_only_of<plc::iec::CTU>(), (Names{"x.cu_prev_"}));
  EXPECT_EQ(read_only_of<plc::iec::CTD>(), (Names{"x.cd_prev_"}));
  EXPECT_EQ(read_only_of<plc::iec::CTUD>(), (Names{"x.cu_prev_", "x.cd_prev_"}));
  EXPECT_EQ(read_only_of<plc::iec::SR>(), Names{});
  EXPECT_EQ(read_only_of<plc::iec::RS>(), Names{});
}

// The reflected references are the live members: a debugger sees the state.
TEST(IecReflection, ReflectsLiveInternalState) {
  plc::iec::TON t;
  plc::ScanContext ctx{.now = 7ms};
  t(ctx, true, 20ms);
  struct Finder {
    plc::TIME start{};
    bool running = false;
    void operator()(const char* n, plc::TIME& v) {
      if (std::string(n) == "start_") start = v;
    }
    void operator()(const char* n, bool& v) {
      if (std::string(n) == "running_") running = v;
    }
  } f;
  t.reflect(f);
  EXPECT_EQ(f.start, plc::TIME(7ms));
  EXPECT_TRUE(f.running);
}

template <class Fb>
constexpr bool plain_v =
    std::is_trivially_copyable_v<Fb> && !std::is_polymorphic_v<Fb> && std::is_standard_layout_v<Fb>;
static_assert(plain_v<plc::iec::TON> && plain_v<plc::iec::TOF> && plain_v<plc::iec::TP>);
static_assert(plain_v<plc::iec::R_TRIG> && plain_v<plc::iec::F_TRIG>);
static_assert(plain_v<plc::iec::CTU> && plain_v<plc::iec::CTD> && plain_v<plc::iec::CTUD>);
static_assert(plain_v<plc::iec::SR> && plain_v<plc::iec::RS>);
// Layout: timers pack their flags after the TIME fields (arrays of thousands).
static_assert(sizeof(plc::iec::TON) == 32 && sizeof(plc::iec::TOF) == 32 &&
              sizeof(plc::iec::TP) == 32);
static_assert(sizeof(plc::iec::R_TRIG) == 3 && sizeof(plc::iec::CTU) == 8);

}  // namespace

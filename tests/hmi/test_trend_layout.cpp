// `plcctl trend --png` (issue 21 point 6): BOOL and integer variables are
// drawn as steps (a sample holds until the next one), REAL and TIME as
// lines; variables go into one panel per IEC type class over a common time
// axis, since the cell description carries no engineering unit
// (hmi-bridge/lcm/var_desc_t.lcm: path, type, address). Tested on the
// layout decisions (trend_layout.hpp); the PNG itself is only checked to be
// written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "trend_layout.hpp"
#include "trend_plot.hpp"

using namespace plc::hmi;

namespace {

// Samples at t = 0, 0.1, ... of: a BOOL, an INT, a REAL, a second BOOL, a
// TIME and a STRING (NaN, as the bridge's trace_sample_t sends it).
Trend mixed_trend(std::size_t samples = 40) {
  Trend tr;
  tr.names = {"Tank.valve_open", "Tank.level",   "Tank.flow",
              "Tank.alarm",      "Tank.hold.ET", "Tank.name"};
  tr.types = {"BOOL", "INT", "REAL", "BOOL", "TIME", "STRING"};
  tr.value.resize(tr.names.size());
  for (std::size_t i = 0; i < samples; ++i) {
    tr.t.push_back(0.1 * double(i));
    tr.value[0].push_back((i / 10) % 2 ? 1.0 : 0.0);
    tr.value[1].push_back(double(i / 5) * 250.0);
    tr.value[2].push_back(2.5 * std::sin(double(i) / 6.0));
    tr.value[3].push_back(i >= 25 ? 1.0 : 0.0);
    tr.value[4].push_back(0.1 * double(i % 20));
    tr.value[5].push_back(std::nan(""));
  }
  return tr;
}

}  // namespace

TEST(PlcctlTrend, TypeClassesFollowTheIecTypeNames) {
  EXPECT_EQ(trend_class("BOOL"), TrendClass::Bool);
  for (const char* t : {"SINT", "INT", "DINT", "LINT", "USINT", "UINT", "UDINT", "ULINT", "BYTE",
                        "WORD", "DWORD", "LWORD"})
    EXPECT_EQ(trend_class(t), TrendClass::Integer) << t;
  EXPECT_EQ(trend_class("REAL"), TrendClass::Real);
  EXPECT_EQ(trend_class("LREAL"), TrendClass::Real);
  EXPECT_EQ(trend_class("TIME"), TrendClass::Time);
  EXPECT_EQ(trend_class("STRING"), std::nullopt);
  EXPECT_EQ(trend_class("bool"), std::nullopt) << "var_desc_t spells types in capitals";
}

TEST(PlcctlTrend, OnePanelPerTypeClassBoolAndIntegersStepped) {
  const auto panels = trend_panels(mixed_trend());
  ASSERT_EQ(panels.size(), 4U) << "BOOL, integer, REAL, TIME; the STRING is left out";
  EXPECT_EQ(panels[0].cls, TrendClass::Bool);
  EXPECT_EQ(panels[0].series, (std::vector<std::size_t>{0, 3}));
  EXPECT_TRUE(panels[0].stepped);
  EXPECT_EQ(panels[1].cls, TrendClass::Integer);
  EXPECT_EQ(panels[1].series, (std::vector<std::size_t>{1}));
  EXPECT_TRUE(panels[1].stepped);
  EXPECT_EQ(panels[2].cls, TrendClass::Real);
  EXPECT_EQ(panels[2].series, (std::vector<std::size_t>{2}));
  EXPECT_FALSE(panels[2].stepped);
  EXPECT_EQ(panels[3].cls, TrendClass::Time);
  EXPECT_EQ(panels[3].y_label, "TIME (s)");
  EXPECT_FALSE(panels[3].stepped);
}

TEST(PlcctlTrend, BoolsGetALaneEachAndOtherPanelsTheirDataRange) {
  const auto panels = trend_panels(mixed_trend());
  ASSERT_EQ(panels.size(), 4U);
  // Two BOOLs: the first on top (offset 1.5), the second at 0, no overlap.
  EXPECT_EQ(panels[0].offset, (std::vector<double>{1.5, 0.0}));
  EXPECT_LT(panels[0].ymin, 0.0);
  EXPECT_GT(panels[0].ymax, 2.5);
  // INT 0 .. 1750 with 5 % padding.
  EXPECT_DOUBLE_EQ(panels[1].ymin, -87.5);
  EXPECT_DOUBLE_EQ(panels[1].ymax, 1837.5);
  EXPECT_EQ(panels[1].offset, (std::vector<double>{0.0}));
  // A trend with only a REAL: one panel, no BOOL lanes.
  Trend only_real = mixed_trend();
  only_real.types = {"STRING", "STRING", "LREAL", "STRING", "STRING", "STRING"};
  const auto one = trend_panels(only_real);
  ASSERT_EQ(one.size(), 1U);
  EXPECT_EQ(one[0].cls, TrendClass::Real);
  EXPECT_LT(one[0].ymin, -2.4);
  EXPECT_GT(one[0].ymax, 2.4);
  // A flat series gets +-1 around its value, not a zero-height axis.
  Trend flat;
  flat.names = {"x"};
  flat.types = {"DINT"};
  flat.t = {0, 1};
  flat.value = {{7, 7}};
  const auto f = trend_panels(flat);
  ASSERT_EQ(f.size(), 1U);
  EXPECT_LT(f[0].ymin, 6.0);
  EXPECT_GT(f[0].ymax, 8.0);
}

TEST(PlcctlTrend, SteppedLineHoldsEachValueUntilTheNextSample) {
  const std::vector<double> t{0.0, 1.0, 2.0, 3.0};
  const std::vector<double> v{0.0, 1.0, std::nan(""), 0.0};  // NaN: not in that snapshot
  const TrendLine s = trend_line(t, v, true, 4.0);
  EXPECT_EQ(s.x, (std::vector<double>{0.0, 1.0, 1.0, 3.0, 3.0, 4.0}));
  EXPECT_EQ(s.y, (std::vector<double>{0.0, 0.0, 1.0, 1.0, 0.0, 0.0}));
  // A REAL: straight lines between its samples, nothing held.
  const TrendLine r = trend_line(t, v, false, 4.0);
  EXPECT_EQ(r.x, (std::vector<double>{0.0, 1.0, 3.0}));
  EXPECT_EQ(r.y, (std::vector<double>{0.0, 1.0, 0.0}));
  // No finite sample: nothing to draw.
  EXPECT_TRUE(trend_line(t, std::vector<double>(4, std::nan("")), true, 4.0).x.empty());
}

TEST(PlcctlTrend, PngIsWrittenWithOnePanelPerTypeClass) {
  const std::string png = ::testing::TempDir() + "plcctl_trend_layout.png";
  std::filesystem::remove(png);
  ASSERT_EQ(write_trend_png(mixed_trend(), png, "demo"), "");
  ASSERT_TRUE(std::filesystem::exists(png));
  EXPECT_GT(std::filesystem::file_size(png), 1000U);
  // Four panels are taller than the one-panel default of 600 pixels (PNG
  // IHDR: width and height, big-endian, at bytes 16..23).
  std::ifstream f(png, std::ios::binary);
  unsigned char head[24] = {};
  f.read(reinterpret_cast<char*>(head), sizeof head);
  const unsigned height = (unsigned(head[20]) << 24) | (unsigned(head[21]) << 16) |
                          (unsigned(head[22]) << 8) | unsigned(head[23]);
  EXPECT_GT(height, 600U);
  Trend strings = mixed_trend();
  strings.types.assign(strings.names.size(), "STRING");
  EXPECT_EQ(write_trend_png(strings, png, "demo"), "no numeric values to draw");
}

// SEL, MAX, MIN, LIMIT, MUX against IEC 61131-3 ed.3 6.6.2.5.12 Table 32
// (ed.2 2.5.1.5.4 Table 27, selection functions).
#include <gtest/gtest.h>

#include <chrono>

#include "plc/fb/iec/selection.hpp"

namespace {

using namespace std::chrono_literals;
using plc::INT;
using plc::REAL;
using plc::TIME;
using namespace plc::iec;

// The functions are constexpr: usable in constant initialisers.
static_assert(LIMIT(INT{0}, INT{150}, INT{100}) == 100);

// IEC 61131-3 Table 32 (ed.2 Table 27), SEL: G = FALSE selects IN0.
TEST(IecTable32_Selection, Sel) {
  EXPECT_EQ(SEL(false, INT{1}, INT{2}), 1);
  EXPECT_EQ(SEL(true, INT{1}, INT{2}), 2);
  EXPECT_EQ(SEL(true, TIME(10ms), TIME(20ms)), TIME(20ms));
}

// IEC 61131-3 Table 32, MAX/MIN: extensible, any position may win.
TEST(IecTable32_Selection, MaxMin) {
  EXPECT_EQ(MAX(INT{3}, INT{-7}, INT{12}, INT{5}), 12);
  EXPECT_EQ(MIN(INT{3}, INT{-7}, INT{12}, INT{5}), -7);
  EXPECT_EQ(MAX(INT{9}), 9);
  EXPECT_EQ(MAX(REAL{1.5f}, REAL{-2.0f}), 1.5f);
  EXPECT_EQ(MIN(TIME(5ms), TIME(3ms)), TIME(3ms));
}

// IEC 61131-3 Table 32, LIMIT(MN, IN, MX) = MIN(MAX(IN, MN), MX).
TEST(IecTable32_Selection, Limit) {
  EXPECT_EQ(LIMIT(INT{0}, INT{-5}, INT{100}), 0);
  EXPECT_EQ(LIMIT(INT{0}, INT{42}, INT{100}), 42);
  EXPECT_EQ(LIMIT(INT{0}, INT{500}, INT{100}), 100);
  EXPECT_EQ(LIMIT(INT{10}, INT{5}, INT{3}), 3);  // MN > MX: the formula gives MX
}

// IEC 61131-3 Table 32, MUX(K, IN0, ...): selects IN<K>; K out of range is
// an error with implementation-specific result: clamped here.
TEST(IecTable32_Selection, Mux) {
  EXPECT_EQ(MUX(0, INT{10}, INT{11}, INT{12}), 10);
  EXPECT_EQ(MUX(2, INT{10}, INT{11}, INT{12}), 12);
  EXPECT_EQ(MUX(1u, INT{10}, INT{11}, INT{12}), 11);
  EXPECT_EQ(MUX(7, INT{10}, INT{11}, INT{12}), 12);
  EXPECT_EQ(MUX(-1, INT{10}, INT{11}, INT{12}), 10);
}

}  // namespace

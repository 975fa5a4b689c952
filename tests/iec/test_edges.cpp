// R_TRIG, F_TRIG against IEC 61131-3 ed.3 6.6.3.5.3 Table 44 (ed.2 2.5.2.3.2
// Table 35): Q := CLK AND NOT M; M := CLK  and  Q := NOT CLK AND NOT M;
// M := NOT CLK, with M initially FALSE. Each row is one call.
#include <gtest/gtest.h>

#include <span>

#include "plc/fb/iec/edges.hpp"

namespace {

struct EdgeRow {
  bool clk;  // CLK
  bool q;    // expected Q
};

template <class Trig>
void run_table(std::span<const EdgeRow> rows) {
  Trig fb;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const bool q = fb(rows[i].clk);
    EXPECT_EQ(q, fb.Q);
    EXPECT_EQ(fb.Q, rows[i].q) << "row " << i << " CLK=" << rows[i].clk;
  }
}

// IEC 61131-3 Table 44, R_TRIG: one Q per rising edge; the first call with
// CLK = TRUE is a rising edge (M initially FALSE).
TEST(IecTable44_R_TRIG, RisingEdges) {
  constexpr EdgeRow rows[] = {
      {true, true},   {true, false},  {false, false}, {true, true},
      {false, false}, {false, false}, {true, true},   {true, false},
  };
  run_table<plc::iec::R_TRIG>(rows);
}

// IEC 61131-3 Table 44, R_TRIG: first call with CLK = FALSE gives nothing.
TEST(IecTable44_R_TRIG, FirstCallFalse) {
  constexpr EdgeRow rows[] = {{false, false}, {false, false}, {true, true}};
  run_table<plc::iec::R_TRIG>(rows);
}

// IEC 61131-3 Table 44, F_TRIG: one Q per falling edge. The standard's body
// with M initially FALSE makes a first call with CLK = FALSE a falling edge.
TEST(IecTable44_F_TRIG, FallingEdgesAndStartupPulse) {
  constexpr EdgeRow rows[] = {
      {false, true},  {false, false}, {true, false}, {false, true},
      {false, false}, {true, false},  {true, false}, {false, true},
  };
  run_table<plc::iec::F_TRIG>(rows);
}

// IEC 61131-3 Table 44, F_TRIG: first call with CLK = TRUE gives nothing.
TEST(IecTable44_F_TRIG, FirstCallTrue) {
  constexpr EdgeRow rows[] = {{true, false}, {true, false}, {false, true}, {true, false}};
  run_table<plc::iec::F_TRIG>(rows);
}

}  // namespace

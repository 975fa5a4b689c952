// SR, RS against IEC 61131-3 ed.3 6.6.3.5.2 Table 43 (ed.2 2.5.2.3.1 Table
// 34): SR Q1 := S1 OR (NOT R AND Q1) (set dominant); RS Q1 := NOT R1 AND
// (S OR Q1) (reset dominant). Each row is one call.
#include <gtest/gtest.h>

#include <span>

#include "plc/fb/iec/bistables.hpp"

namespace {

struct BistableRow {
  bool set;    // S1 (SR) or S (RS)
  bool reset;  // R (SR) or R1 (RS)
  bool q1;     // expected Q1
};

template <class Fb>
void run_table(std::span<const BistableRow> rows) {
  Fb fb;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const bool q = fb(rows[i].set, rows[i].reset);
    EXPECT_EQ(q, fb.Q1);
    EXPECT_EQ(fb.Q1, rows[i].q1) << "row " << i;
  }
}

// IEC 61131-3 Table 43, SR: set dominant, Q1 holds between set and reset.
TEST(IecTable43_SR, SetDominant) {
  constexpr BistableRow rows[] = {
      {false, false, false}, {true, false, true},  {false, false, true},
      {false, true, false},  {true, true, true},  // both: set wins
      {false, false, true},  {false, true, false}, {false, false, false},
  };
  run_table<plc::iec::SR>(rows);
}

// IEC 61131-3 Table 43, RS: reset dominant, Q1 holds between set and reset.
TEST(IecTable43_RS, ResetDominant) {
  constexpr BistableRow rows[] = {
      {false, false, false}, {true, false, true}, {false, false, true},
      {false, true, false},  {true, false, true}, {true, true, false},  // reset wins
      {false, false, false}, {true, false, true},
  };
  run_table<plc::iec::RS>(rows);
}

}  // namespace

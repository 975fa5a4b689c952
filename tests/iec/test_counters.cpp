// CTU, CTD, CTUD against IEC 61131-3 ed.3 6.6.3.5.4 Table 45 (ed.2 2.5.2.3.3
// Table 36): CU/CD are R_EDGE inputs, CV saturates at the type's limits
// (PVmax/PVmin), CTUD's R has priority over LD. Each row is one call.
#include <gtest/gtest.h>

#include <limits>
#include <span>

#include "plc/fb/iec/counters.hpp"

namespace {

using plc::INT;

struct CtuRow {
  bool cu, r;
  int pv;
  bool q;  // expected
  int cv;  // expected
};

template <class Ctu>
void run_ctu(Ctu& fb, std::span<const CtuRow> rows) {
  using T = decltype(fb.CV);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CtuRow& r = rows[i];
    const bool q = fb(r.cu, r.r, static_cast<T>(r.pv));
    EXPECT_EQ(q, fb.Q);
    EXPECT_EQ(fb.Q, r.q) << "row " << i;
    EXPECT_EQ(fb.CV, static_cast<T>(r.cv)) << "row " << i;
  }
}

// IEC 61131-3 Table 45, CTU: counts rising edges of CU, Q = CV >= PV, R resets;
// a first call with CU = TRUE counts (R_EDGE memory initially FALSE); CU held
// TRUE through a reset does not count again when R falls.
TEST(IecTable45_CTU, CountsRisingEdges) {
  constexpr CtuRow rows[] = {
      {true, false, 3, false, 1},  // first call CU TRUE: counted
      {true, false, 3, false, 1},  // held: no count
      {false, false, 3, false, 1}, {true, false, 3, false, 2},
      {false, false, 3, false, 2}, {true, false, 3, true, 3},   // CV = PV
      {false, false, 3, true, 3},  {true, false, 3, true, 4},   // beyond PV
      {false, true, 3, false, 0},                               // reset
      {true, true, 3, false, 0},                                // edge during reset: not counted
      {true, false, 3, false, 0},                               // CU still TRUE after R: no edge
      {false, false, 3, false, 0}, {false, false, 0, true, 0},  // PV = 0: Q
      {true, false, 0, true, 1},
  };
  plc::iec::CTU fb;
  run_ctu(fb, rows);
}

// IEC 61131-3 Table 45, CTU: CV saturates at PVmax (INT: 32767), no wrap.
TEST(IecTable45_CTU, SaturatesAtTypeMaximum) {
  constexpr CtuRow rows[] = {
      {true, false, 32767, false, 32766}, {false, false, 32767, false, 32766},
      {true, false, 32767, true, 32767},  {false, false, 32767, true, 32767},
      {true, false, 32767, true, 32767},  {false, false, 32767, true, 32767},
      {true, false, 32767, true, 32767},
  };
  plc::iec::CTU fb;
  fb.CV = 32765;
  run_ctu(fb, rows);
}

// IEC 61131-3 Table 45, CTU_UDINT (ed.3 typed variant): saturates at 2^32-1.
TEST(IecTable45_CTU, UdintSaturatesAtTypeMaximum) {
  plc::iec::CTU_UDINT fb;
  fb.CV = std::numeric_limits<plc::UDINT>::max() - 1;
  fb(true, false, 5);
  EXPECT_EQ(fb.CV, std::numeric_limits<plc::UDINT>::max());
  fb(false, false, 5);
  fb(true, false, 5);
  EXPECT_EQ(fb.CV, std::numeric_limits<plc::UDINT>::max());
  EXPECT_TRUE(fb.Q);
}

struct CtdRow {
  bool cd, ld;
  int pv;
  bool q;
  int cv;
};

template <class Ctd>
void run_ctd(Ctd& fb, std::span<const CtdRow> rows) {
  using T = decltype(fb.CV);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CtdRow& r = rows[i];
    const bool q = fb(r.cd, r.ld, static_cast<T>(r.pv));
    EXPECT_EQ(q, fb.Q);
    EXPECT_EQ(fb.Q, r.q) << "row " << i;
    EXPECT_EQ(fb.CV, static_cast<T>(r.cv)) << "row " << i;
  }
}

// IEC 61131-3 Table 45, CTD: LD loads PV, rising edges of CD count down,
// Q = CV <= 0, counting goes on below 0; LD has priority over a CD edge.
TEST(IecTable45_CTD, CountsDownFromPreset) {
  constexpr CtdRow rows[] = {
      {false, false, 2, true, 0},                               // CV initially 0: Q
      {false, true, 2, false, 2},                               // load
      {true, false, 2, false, 1},  {true, false, 2, false, 1},  // held
      {false, false, 2, false, 1}, {true, false, 2, true, 0},
      {false, false, 2, true, 0},  {true, false, 2, true, -1},  // below 0
      {false, false, 2, true, -1}, {true, true, 5, false, 5},   // LD wins
      {false, false, 5, false, 5},
  };
  plc::iec::CTD fb;
  run_ctd(fb, rows);
}

// IEC 61131-3 Table 45, CTD: CV saturates at PVmin (INT: -32768), no wrap.
TEST(IecTable45_CTD, SaturatesAtTypeMinimum) {
  constexpr CtdRow rows[] = {
      {true, false, 0, true, -32767}, {false, false, 0, true, -32767},
      {true, false, 0, true, -32768}, {false, false, 0, true, -32768},
      {true, false, 0, true, -32768},
  };
  plc::iec::CTD fb;
  fb.CV = -32766;
  run_ctd(fb, rows);
}

// IEC 61131-3 Table 45, CTD_UDINT: PVmin of an unsigned type is 0.
TEST(IecTable45_CTD, UdintStopsAtZero) {
  plc::iec::CTD_UDINT fb;
  fb(false, true, 1);
  fb(true, false, 1);
  EXPECT_EQ(fb.CV, 0u);
  fb(false, false, 1);
  fb(true, false, 1);
  EXPECT_EQ(fb.CV, 0u);
  EXPECT_TRUE(fb.Q);
}

struct CtudRow {
  bool cu, cd, r, ld;
  int pv;
  bool qu, qd;  // expected
  int cv;       // expected
};

void run_ctud(plc::iec::CTUD& fb, std::span<const CtudRow> rows) {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CtudRow& r = rows[i];
    fb(r.cu, r.cd, r.r, r.ld, static_cast<INT>(r.pv));
    EXPECT_EQ(fb.QU, r.qu) << "row " << i;
    EXPECT_EQ(fb.QD, r.qd) << "row " << i;
    EXPECT_EQ(fb.CV, r.cv) << "row " << i;
  }
}

// IEC 61131-3 Table 45, CTUD: up and down on rising edges, simultaneous edges
// do not count, LD loads PV, R resets and has priority over LD.
TEST(IecTable45_CTUD, UpDownResetLoad) {
  constexpr CtudRow rows[] = {
      // cu     cd     r      ld    pv  qu     qd     cv
      {false, false, false, false, 2, false, true, 0},
      {true, false, false, false, 2, false, false, 1},
      {false, false, false, false, 2, false, false, 1},
      {true, false, false, false, 2, true, false, 2},   // QU at PV
      {false, true, false, false, 2, false, false, 1},  // down
      {false, false, false, false, 2, false, false, 1},
      {true, true, false, false, 2, false, false, 1},   // both edges: no count
      {false, false, false, true, 2, true, false, 2},   // LD
      {false, false, true, true, 2, false, true, 0},    // R and LD: R wins
      {true, false, true, false, 2, false, true, 0},    // R holds
      {true, false, false, false, 2, false, true, 0},   // CU held: no edge
      {false, true, false, false, 2, false, true, -1},  // below 0: QD
      {false, false, false, true, 7, true, false, 7},   // load new PV: QU
  };
  plc::iec::CTUD fb;
  run_ctud(fb, rows);
}

// IEC 61131-3 Table 45, CTUD: CV saturates at both INT limits, no wrap.
TEST(IecTable45_CTUD, SaturatesAtBothLimits) {
  plc::iec::CTUD fb;
  fb.CV = std::numeric_limits<INT>::max();
  fb(true, false, false, false, 10);
  EXPECT_EQ(fb.CV, std::numeric_limits<INT>::max());
  EXPECT_TRUE(fb.QU);
  fb.CV = std::numeric_limits<INT>::min();
  fb(false, true, false, false, 10);
  EXPECT_EQ(fb.CV, std::numeric_limits<INT>::min());
  EXPECT_TRUE(fb.QD);
}

}  // namespace

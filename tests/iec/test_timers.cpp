// TON, TOF, TP against the timing diagrams of IEC 61131-3 ed.3 6.6.3.5.5
// Table 46 (ed.2 2.5.2.3.4 Tables 37/38), plus the implementation-specific
// cases (PT = 0, PT change while running) as documented in the headers.
// Each row is one scan: the scan time, the inputs, the expected outputs.
#include <gtest/gtest.h>

#include <chrono>
#include <span>

#include "plc/fb/iec/tof.hpp"
#include "plc/fb/iec/ton.hpp"
#include "plc/fb/iec/tp.hpp"

namespace {

using namespace std::chrono_literals;
using plc::ScanContext;
using plc::TIME;

struct TimerRow {
  int t_ms;   // scan time
  bool in;    // IN
  int pt_ms;  // PT
  bool q;     // expected Q
  int et_ms;  // expected ET
};

template <class Timer>
void run_table(std::span<const TimerRow> rows) {
  Timer fb;
  ScanContext ctx;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const TimerRow& r = rows[i];
    ctx.now = std::chrono::milliseconds(r.t_ms);
    ctx.cycle = i;
    const bool q = fb(ctx, r.in, std::chrono::milliseconds(r.pt_ms));
    EXPECT_EQ(q, fb.Q) << "call helper returns Q";
    EXPECT_EQ(fb.Q, r.q) << "row " << i << " t=" << r.t_ms << "ms IN=" << r.in;
    EXPECT_EQ(fb.ET, TIME(std::chrono::milliseconds(r.et_ms)))
        << "row " << i << " t=" << r.t_ms << "ms IN=" << r.in;
  }
}

// ---- TON --------------------------------------------------------------

// IEC 61131-3 Table 46 (ed.2 Table 38), timing diagram TON: Q rises PT after
// the rising edge of IN, ET ramps to PT and is clamped, a pulse of IN shorter
// than PT gives no Q, IN = FALSE resets Q and ET.
TEST(IecTable46_TON, TimingDiagram) {
  // One scan per line: t_ms, IN, PT_ms, expected Q, expected ET_ms.
  // clang-format off
  constexpr TimerRow rows[] = {
      {0,   false, 10,  false, 0},
      {5,   true,  10,  false, 0},  // rising edge at 5
      {10,  true,  10,  false, 5},
      {14,  true,  10,  false, 9},
      {15,  true,  10,  true,  10},  // t0 + PT
      {30,  true,  10,  true,  10},  // ET clamped at PT
      {31,  false, 10,  false, 0},  // reset
      {32,  true,  10,  false, 0},
      {38,  true,  10,  false, 6},
      {39,  false, 10,  false, 0},  // shorter than PT
      {40,  true,  10,  false, 0},
      {49,  true,  10,  false, 9},
      {50,  true,  10,  true,  10},
      {51,  false, 10,  false, 0},
  };
  // clang-format on
  run_table<plc::iec::TON>(rows);
}

// IEC 61131-3 Table 46: first call with IN = TRUE is a rising edge (IN is
// taken as FALSE before the first scan), timing starts on that scan.
TEST(IecTable46_TON, FirstCallWithInTrueStartsTiming) {
  // One scan per line: t_ms, IN, PT_ms, expected Q, expected ET_ms.
  // clang-format off
  constexpr TimerRow rows[] = {
      {100, true,  20,  false, 0},
      {119, true,  20,  false, 19},
      {120, true,  20,  true,  20},
  };
  // clang-format on
  run_table<plc::iec::TON>(rows);
}

// IEC 61131-3 Table 46, TON with PT = T#0s: Q follows IN on the same scan.
TEST(IecTable46_TON, PresetZeroFollowsInput) {
  // One scan per line: t_ms, IN, PT_ms, expected Q, expected ET_ms.
  // clang-format off
  constexpr TimerRow rows[] = {
      {0,   false, 0,   false, 0},
      {1,   true,  0,   true,  0},
      {2,   true,  0,   true,  0},
      {3,   false, 0,   false, 0},
      {4,   true,  0,   true,  0},
  };
  // clang-format on
  run_table<plc::iec::TON>(rows);
}

// IEC 61131-3 Table 46 note (PT change during timing is implementation-
// specific): before expiry the new PT applies at once; after expiry Q is
// latched and ET keeps the PT it expired with.
TEST(IecTable46_TON, PresetChangeWhileRunning) {
  // One scan per line: t_ms, IN, PT_ms, expected Q, expected ET_ms.
  // clang-format off
  constexpr TimerRow rows[] = {
      {0,   true,  10,  false, 0},
      {5,   true,  20,  false, 5},  // PT raised before expiry: runs on to 20
      {15,  true,  20,  false, 15},
      {19,  true,  20,  false, 19},
      {20,  true,  20,  true,  20},  // expires at the new PT
      {25,  true,  50,  true,  20},  // raised after expiry: Q latched, ET held
      {26,  false, 50,  false, 0},
      {30,  true,  50,  false, 0},
      {40,  true,  50,  false, 10},
      {41,  true,  5,   true,  5},  // lowered below elapsed: expires at once
      {42,  true,  5,   true,  5},
  };
  // clang-format on
  run_table<plc::iec::TON>(rows);
}

// TON with a 1 ms task: PT = T#20ms gives Q on exactly the 20th scan after
// the rising edge (IEC 61131-3 Table 46, Q at t0 + PT).
TEST(IecTable46_TON, VirtualTimeScanLoop) {
  plc::iec::TON t;
  ScanContext ctx;
  int first_q_scan = -1;
  for (int scan = 0; scan < 40; ++scan) {
    ctx.now = std::chrono::milliseconds(scan);
    t(ctx, scan >= 3, 20ms);
    if (t.Q && first_q_scan < 0) first_q_scan = scan;
  }
  EXPECT_EQ(first_q_scan, 23);
  EXPECT_EQ(t.ET, TIME(20ms));
}

// ---- TOF --------------------------------------------------------------

// IEC 61131-3 Table 46 (ed.2 Table 38), timing diagram TOF: Q is TRUE with IN
// and stays TRUE for PT after the falling edge; ET ramps after the falling
// edge, is held at PT until IN rises again; IN rising during the delay
// restarts it.
TEST(IecTable46_TOF, TimingDiagram) {
  // One scan per line: t_ms, IN, PT_ms, expected Q, expected ET_ms.
  // clang-format off
  constexpr TimerRow rows[] = {
      {0,   false, 10,  false, 0},  // first call with IN = FALSE: no falling edge
      {5,   false, 10,  false, 0},
      {10,  true,  10,  true,  0},
      {15,  true,  10,  true,  0},
      {20,  false, 10,  true,  0},  // falling edge at 20
      {25,  false, 10,  true,  5},
      {29,  false, 10,  true,  9},
      {30,  false, 10,  false, 10},  // t1 + PT
      {40,  false, 10,  false, 10},  // ET held at PT while IN stays FALSE
      {41,  true,  10,  true,  0},
      {45,  false, 10,  true,  0},  // falling at 45
      {50,  true,  10,  true,  0},  // IN back before expiry: no Q gap
      {51,  false, 10,  true,  0},  // falling at 51: delay restarts
      {60,  false, 10,  true,  9},
      {61,  false, 10,  false, 10},
  };
  // clang-format on
  run_table<plc::iec::TOF>(rows);
}

// IEC 61131-3 Table 46, TOF with PT = T#0s: Q follows IN on the same scan.
TEST(IecTable46_TOF, PresetZeroFollowsInput) {
  // One scan per line: t_ms, IN, PT_ms, expected Q, expected ET_ms.
  // clang-format off
  constexpr TimerRow rows[] = {
      {0,   true,  0,   true,  0},
      {1,   false, 0,   false, 0},
      {2,   false, 0,   false, 0},
      {3,   true,  0,   true,  0},
      {4,   false, 0,   false, 0},
  };
  // clang-format on
  run_table<plc::iec::TOF>(rows);
}

// IEC 61131-3 Table 46 note: PT change during the off-delay applies at once;
// after expiry Q stays FALSE whatever PT becomes.
TEST(IecTable46_TOF, PresetChangeWhileRunning) {
  // One scan per line: t_ms, IN, PT_ms, expected Q, expected ET_ms.
  // clang-format off
  constexpr TimerRow rows[] = {
      {0,   true,  10,  true,  0},
      {10,  false, 10,  true,  0},
      {15,  false, 30,  true,  5},  // raised during the delay
      {39,  false, 30,  true,  29},
      {40,  false, 30,  false, 30},
      {50,  false, 100, false, 30},  // raised after expiry: Q stays FALSE
      {60,  true,  100, true,  0},
      {61,  false, 100, true,  0},
      {70,  false, 5,   false, 5},  // lowered below elapsed: expires at once
  };
  // clang-format on
  run_table<plc::iec::TOF>(rows);
}

// ---- TP ---------------------------------------------------------------

// IEC 61131-3 Table 46 (ed.2 Table 38), timing diagram TP: the pulse runs its
// full PT even if IN falls, is not retriggerable, and a new pulse needs a new
// rising edge after the pulse ended. ET holds PT after the pulse while IN is
// TRUE and is 0 once IN is FALSE.
TEST(IecTable46_TP, TimingDiagram) {
  // One scan per line: t_ms, IN, PT_ms, expected Q, expected ET_ms.
  // clang-format off
  constexpr TimerRow rows[] = {
      {0,   false, 10,  false, 0},
      {5,   true,  10,  true,  0},  // rising edge: pulse starts
      {8,   false, 10,  true,  3},  // IN falls: pulse goes on
      {9,   true,  10,  true,  4},  // retrigger attempt: ignored
      {12,  false, 10,  true,  7},
      {14,  true,  10,  true,  9},  // ignored again
      {15,  true,  10,  false, 10},  // pulse ends at 5 + PT; ET holds PT (IN TRUE)
      {20,  true,  10,  false, 10},  // IN still TRUE: no new pulse
      {25,  false, 10,  false, 0},  // IN FALSE: ET back to 0
      {30,  true,  10,  true,  0},  // new rising edge: new pulse
      {31,  false, 10,  true,  1},
      {40,  false, 10,  false, 0},  // ends with IN FALSE: ET to 0 at once
  };
  // clang-format on
  run_table<plc::iec::TP>(rows);
}

// IEC 61131-3 Table 46, TP: a rising edge on the scan where the pulse ends
// starts the next pulse (Q is TRUE on start <= t < start + PT); a first call
// with IN = TRUE is a rising edge.
TEST(IecTable46_TP, EdgeAtPulseEndAndFirstCall) {
  // One scan per line: t_ms, IN, PT_ms, expected Q, expected ET_ms.
  // clang-format off
  constexpr TimerRow rows[] = {
      {50,  true,  10,  true,  0},
      {55,  false, 10,  true,  5},
      {60,  true,  10,  true,  0},  // old pulse over at 60, edge at 60: new pulse
      {69,  true,  10,  true,  9},
      {70,  true,  10,  false, 10},
      {75,  true,  10,  false, 10},  // held TRUE: still no new pulse
  };
  // clang-format on
  run_table<plc::iec::TP>(rows);
}

// IEC 61131-3 Table 46, TP with PT = T#0s: a zero-length pulse, Q stays FALSE.
TEST(IecTable46_TP, PresetZeroGivesNoPulse) {
  // One scan per line: t_ms, IN, PT_ms, expected Q, expected ET_ms.
  // clang-format off
  constexpr TimerRow rows[] = {
      {0,   true,  0,   false, 0},
      {1,   true,  0,   false, 0},
      {2,   false, 0,   false, 0},
      {3,   true,  0,   false, 0},
  };
  // clang-format on
  run_table<plc::iec::TP>(rows);
}

// IEC 61131-3 Table 46 note: PT change during the pulse applies at once;
// PT = T#0s ends a running pulse (the note's "reset a TP instance").
TEST(IecTable46_TP, PresetChangeWhileRunning) {
  // One scan per line: t_ms, IN, PT_ms, expected Q, expected ET_ms.
  // clang-format off
  constexpr TimerRow rows[] = {
      {0,   true,  10,  true,  0},
      {5,   true,  20,  true,  5},  // lengthened
      {19,  true,  20,  true,  19},
      {20,  true,  20,  false, 20},
      {21,  false, 20,  false, 0},
      {30,  true,  10,  true,  0},
      {32,  true,  0,   false, 0},  // PT = 0 ends it
      {33,  false, 10,  false, 0},
      {34,  true,  10,  true,  0},  // next edge works
  };
  // clang-format on
  run_table<plc::iec::TP>(rows);
}

}  // namespace

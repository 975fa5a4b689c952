// A small filling program, built in several versions into cell libraries
// for the online-change tests (FILLER_VERSION):
//   1  the running version;
//   2  the new build: same logic, one field added (alarms, set by init()),
//      one removed (note), one retyped (flow REAL -> LREAL), and `build` = 2;
//   3  the lamp moved from %QX0.0 to %QX0.1 (refused: I/O layout);
//   4  its constructor throws (refused);
//   5  calls a function no library defines (dlopen fails: undefined symbol).
// Its state: a step sequence (idle, filling, settling, done) with the
// weight growing by `flow` per scan, a TON settle timer and a dwell TON that
// runs continuously, a CTU batch counter.
#include <stdexcept>

#include "plc/fb/iec/iec.hpp"
#include "plc/io/located.hpp"
#include "plc/program.hpp"

using namespace plc;
using namespace std::chrono_literals;

#if FILLER_VERSION == 5
extern "C" int softplc_test_symbol_that_nobody_defines();
#endif

class Filler : public ProgramBase<Filler> {
 public:
#if FILLER_VERSION == 3
  io::Located<BOOL> lamp{"%QX0.1"};
#else
  io::Located<BOOL> lamp{"%QX0.0"};
#endif
  INT step = 0;  // 0 idle, 1 filling, 2 settling, 3 done
  LREAL weight = 0;
  LREAL target = 25.0;
#if FILLER_VERSION == 2
  LREAL flow = 0.125;
  DINT alarms = 0;  // new in version 2: init() gives it its initial value, 7
  DINT build = 2;
#else
  REAL flow = 0.125F;
  INT note = 42;  // gone in version 2
  DINT build = 1;
#endif
  iec::TON settle;
  iec::TON dwell;  // runs all the time: IN = TRUE
  iec::CTU batches;

#if FILLER_VERSION == 4
  Filler() { throw std::runtime_error("bad version 4"); }
#endif
#if FILLER_VERSION == 2
  // Also on the programs of an online change, before the values carry
  // over: the new field gets its value here, the carried weight keeps its
  // (the first scan of a cold start sets it to 0 anyway).
  void init() override {
    alarms = 7;
    weight = -1;
  }
#endif

  void cycle(const ScanContext& ctx) override {
#if FILLER_VERSION == 5
    step = INT(softplc_test_symbol_that_nobody_defines());
#endif
    build = FILLER_VERSION;  // which code runs
    dwell(ctx, true, 1h);
    switch (step) {
      case 0:
        weight = 0;
        step = 1;
        break;
      case 1:
        weight += flow;
        if (weight >= target) step = 2;
        break;
      case 2:
        settle(ctx, true, 300ms);
        if (settle.Q) step = 3;
        break;
      default:
        settle(ctx, false, 300ms);
        step = 0;
        break;
    }
    batches(step == 3, false, 1000);
    lamp = step == 1;
  }

#if FILLER_VERSION == 2
  PLC_REFLECT(lamp, step, weight, target, flow, alarms, build, settle, dwell, batches)
#else
  PLC_REFLECT(lamp, step, weight, target, flow, note, build, settle, dwell, batches)
#endif
};
PLC_REGISTER_PROGRAM(Filler)

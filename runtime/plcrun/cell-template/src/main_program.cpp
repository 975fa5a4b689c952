// The cell's program: a lamp that blinks 0.5 s on, 0.5 s off while enabled,
// and counts its blinks. Programs are C++ classes with function blocks as
// members; PLC_REFLECT lists the fields the debugger, trace, retain and
// online change see.
#include "plc/fb/iec/iec.hpp"
#include "plc/io/located.hpp"
#include "plc/program.hpp"

using namespace plc;
using namespace std::chrono_literals;

class MainProgram : public ProgramBase<MainProgram> {
 public:
  io::Located<BOOL> lamp{"%QX0.0"};
  BOOL enable = true;  // settable with init: in cell.yaml, or `write` in the debugger
  TIME half_period = 500ms;
  DINT blinks = 0;
  iec::TON on_timer;
  iec::TON off_timer;

  void cycle(const ScanContext& ctx) override {
    on_timer(ctx, enable && !off_timer.Q && !lamp, half_period);
    if (on_timer.Q) {
      lamp = true;
      ++blinks;
    }
    off_timer(ctx, BOOL(lamp), half_period);
    if (off_timer.Q) lamp = false;
  }

  PLC_REFLECT(lamp, enable, half_period, blinks, on_timer, off_timer)
};
PLC_REGISTER_PROGRAM(MainProgram)

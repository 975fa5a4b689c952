// programs/conveyor/conveyor.cpp
#include "plc/fb/iec/iec.hpp"
#include "plc/io/located.hpp"
#include "plc/program.hpp"

using namespace plc;
using namespace std::chrono_literals;

class Conveyor : public ProgramBase<Conveyor> {
 public:
  io::Located<BOOL> start{"%IX0.0"};  // located variables (moveable with bind:)
  io::Located<BOOL> stop{"%IX0.1"};
  io::Located<BOOL> motor{"%QX0.0"};
  io::Located<INT> speed_sp{"%QW2"};

  TIME run_on = 5s;  // a parameter (settable with init:)
  BOOL running = false;
  iec::R_TRIG start_edge;
  iec::TOF after_run;

  void cycle(const ScanContext& ctx) override {
    start_edge(start);  // IEC-style call with inputs
    if (start_edge.Q) running = true;
    if (stop) running = false;
    after_run(ctx, running, run_on);  // timers take the scan context (time)
    motor = after_run.Q;
    speed_sp = INT(running ? 13824 : 0);  // 50 % of 27648
  }

  PLC_REFLECT(start, stop, motor, speed_sp, run_on, running, start_edge, after_run)
};
PLC_REGISTER_PROGRAM(Conveyor)

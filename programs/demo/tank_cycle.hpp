// The demo cell's fast program: fill a tank to a high level, hold, drain to
// a low level, count the batch, repeat. The tank is the sim plugin's
// `first_order` model (an S7-style analog level 0..27648, a valve 0..27648).
#pragma once

#include "plc/fb/iec/iec.hpp"
#include "plc/io/located.hpp"
#include "plc/program.hpp"

namespace demo {

using namespace plc;

class TankCycle : public ProgramBase<TankCycle> {
 public:
  enum class Step : INT { Fill = 1, Hold = 2, Drain = 3 };

  // I/O, located in the image (the tank device sits at %IB0 / %QB0).
  io::Located<INT> level{"%IW0"};
  io::Located<WORD> tank_status{"%IW2"};
  io::Located<INT> valve{"%QW0"};
  io::Located<BOOL> enable{"%MX0.0"};     // written by the Supervisor task
  io::Located<DINT> batches_out{"%MD4"};  // read by the Supervisor task

  // Parameters (can be set from the config's `init:`).
  INT high_level = 22000;
  INT low_level = 4000;
  TIME hold_time = std::chrono::seconds(2);

  // State.
  Step step = Step::Fill;
  iec::TON hold;
  iec::R_TRIG drained;
  iec::CTU batches;

  void init() override { batches.PV = 32767; }

  void cycle(const ScanContext& ctx) override {
    if (!enable) {
      valve = 0;
      return;
    }
    switch (step) {
      case Step::Fill:
        valve = 27648;
        if (level >= high_level) step = Step::Hold;
        break;
      case Step::Hold:
        valve = INT(level < high_level ? 16000 : 8000);  // keep the level near the top
        break;
      case Step::Drain:
        valve = 0;
        if (level <= low_level) step = Step::Fill;
        break;
    }
    hold.IN = step == Step::Hold;
    hold.PT = hold_time;
    hold(ctx);
    if (hold.Q) step = Step::Drain;
    drained.CLK = step == Step::Drain && level <= low_level + 100;
    drained();
    batches.CU = drained.Q;
    batches.R = false;
    batches();
    batches_out = DINT(batches.CV);
  }

  PLC_REFLECT(level, tank_status, valve, enable, batches_out, high_level, low_level, hold_time,
              step, hold, drained, batches)
};

}  // namespace demo

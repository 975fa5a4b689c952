// The demo cell's slow program (10 ms task): enables the tank cycle after a
// start delay and watches the batch count it publishes in %MD4.
#include "plc/fb/iec/iec.hpp"
#include "plc/io/located.hpp"
#include "plc/program.hpp"

namespace demo {

using namespace plc;

class Supervisor : public ProgramBase<Supervisor> {
 public:
  io::Located<BOOL> enable{"%MX0.0"};
  io::Located<DINT> batches{"%MD4"};
  io::Located<BOOL> lamp_running{"%QX2.0"};

  TIME start_delay = std::chrono::milliseconds(500);
  iec::TON start_timer;
  DINT batches_seen = 0;

  void cycle(const ScanContext& ctx) override {
    start_timer.IN = true;
    start_timer.PT = start_delay;
    start_timer(ctx);
    enable = start_timer.Q;
    lamp_running = start_timer.Q;
    batches_seen = batches;
  }

  PLC_REFLECT(enable, batches, lamp_running, start_delay, start_timer, batches_seen)
};

PLC_REGISTER_PROGRAM(Supervisor)

}  // namespace demo

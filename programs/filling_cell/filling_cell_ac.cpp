#include "filling_cell_ac.hpp"

#include "filling_station.hpp"

namespace cell {

FillingCellAc::FillingCellAc() {
  conveyor.Port.set_device_name("conveyor");
  conveyor.Enable = true;
  set_up_filling_station(guard, scale, dose, target_kg);
}

void FillingCellAc::cycle(const ScanContext& ctx) {
  guard.OSSD1 = run;
  guard(ctx);
  const bool safe = !guard.QBAD && guard.OSSD1_ON;
  scale(ctx);
  // The belt runs only with the safety good, the scale on line and the
  // drive under network control without a fault.
  const bool ok = run && safe && scale.Online && conveyor.Valid && !conveyor.Faulted;

  switch (step) {
    case Step::WaitReady:
      if (ok && !conveyor.Running) step = Step::Index;
      break;
    case Step::Index:
      if (index_timer.Q) step = Step::Settle;
      break;
    case Step::Settle:  // belt ramping down: fill a standing container
      if (!conveyor.Running) step = Step::Fill;
      break;
    case Step::Fill:
      dose.TargetWeight = target_kg;
      dose.Execute = !dose.Done;
      if (dose.Done) {
        ++containers;
        step = Step::WaitReady;
      }
      break;
    case Step::Fault: {
      // A drive fault (e.g. 18 after a lost connection) is reset once the
      // drive is reachable again; then the cell starts over. A reset pulse
      // the drive never saw (it fell between two late polls) leaves the
      // fault standing, and a request held high makes no new edge: when
      // the fault is still there reset_pause after the pulse, the request
      // drops for one scan and rises again (a new pulse), at most
      // reset_retries times. Then the cell waits in Fault for the operator
      // (run off and on again grants new retries).
      const bool faulted = conveyor.Valid && conveyor.Faulted;
      reset_wait(ctx, faulted && conveyor.FaultReset && !conveyor.ResetActive, reset_pause);
      if (!run) reset_attempts = 0;
      if (reset_wait.Q) {
        conveyor.FaultReset = false;
        ++reset_attempts;
      } else {
        conveyor.FaultReset = faulted && reset_attempts <= reset_retries;
      }
      if (ok && !conveyor.ResetActive) {
        conveyor.FaultReset = false;
        reset_attempts = 0;
        step = Step::WaitReady;
      }
      break;
    }
  }
  if (!ok && step != Step::Fault && step != Step::Fill) step = Step::WaitReady;
  index_timer.IN = step == Step::Index;
  index_timer.PT = index_time;
  index_timer(ctx);
  conveyor.RunFwd = ok && step == Step::Index;
  conveyor.SpeedRef = belt_speed;
  conveyor(ctx);
  if (step != Step::Fill) dose.Execute = false;
  dose(ctx);

  fault_edge(conveyor.Error || dose.Error);
  if (fault_edge.Q) {
    last_error = conveyor.Error ? conveyor.ErrorID : dose.ErrorID;
    step = Step::Fault;
    dose.Execute = false;
  }
}

PLC_REGISTER_PROGRAM(FillingCellAc)

}  // namespace cell

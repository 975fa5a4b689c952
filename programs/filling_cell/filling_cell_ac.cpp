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
    case Step::Fault:
      // A drive fault (e.g. 18 after a lost connection) is reset once the
      // drive is reachable again; then the cell starts over.
      conveyor.FaultReset = conveyor.Valid && conveyor.Faulted;
      if (ok && !conveyor.ResetActive) {
        conveyor.FaultReset = false;
        step = Step::WaitReady;
      }
      break;
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

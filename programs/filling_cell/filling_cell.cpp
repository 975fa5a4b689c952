#include "filling_cell.hpp"

#include "filling_station.hpp"

namespace cell {

FillingCell::FillingCell() {
  conveyor.Port.set_device_name("conveyor");
  // Three blocks on the conveyor: the cell writes its telegram once per
  // scan, after the last of them (DriveAxis::set_program_commits).
  conveyor.set_program_commits(true);
  set_up_filling_station(guard, scale, dose, target_kg);
}

// The step Fill of the sequence (cycle() takes it first: most scans).
inline void FillingCell::fill_step() {
  dose.TargetWeight = target_kg;
  dose.Execute = !dose.Done;
  if (dose.Done) {
    ++containers;
    step = Step::Index;
  }
}

// Every step of the sequence but Fill.
inline void FillingCell::other_step(bool safe, bool scale_ok) {
  switch (step) {
    case Step::WaitSafety:
      if (safe && run && scale_ok) step = Step::Enable;
      break;
    case Step::Enable:
      if (power.Status) step = Step::Index;
      break;
    case Step::Index:
      index.Distance = pitch;
      index.Velocity = index_velocity;
      index.Execute = !index.Done;
      if (index.Done) step = Step::Fill;
      break;
    case Step::Fill:
      fill_step();
      break;
    case Step::Fault:
      // Acknowledge the axis error (drive fault or lost communication) and
      // start over once the safety is good again. Enable is FALSE in this
      // step, so MC_Reset leaves the conveyor Disabled and the sequence
      // powers it again from WaitSafety, after the safety and scale checks
      // (an Enable held through MC_Reset would re-enable it at once).
      reset.Execute = safe;
      if (reset.Done || conveyor.State != drive::AxisState::ErrorStop) {
        reset.Execute = false;
        step = Step::WaitSafety;
      }
      break;
  }
}

void FillingCell::cycle(const ScanContext& ctx) {
  // Safety first: request STO release while running; the conveyor may be
  // powered only while the module exchanges good data and reports OSSD1 on.
  guard.OSSD1 = run;
  guard(ctx);
  const bool safe = !guard.QBAD && guard.OSSD1_ON;

  scale(ctx);
  // No scale, no filling: the conveyor is not powered while the scale is
  // off line (a lost fieldbus slave), so it never indexes containers that
  // cannot be filled.
  const bool scale_ok = scale.Online;
  power.Enable = run && safe && scale_ok && step != Step::Fault;
  power(ctx, conveyor);

  // Fill first: dosing a container takes seconds against the index move's
  // fraction of one, so most scans are in Fill; one compare takes them
  // there, not the switch's bounds check and jump table (the same step).
  if (step == Step::Fill) [[likely]] {
    fill_step();
  } else {
    other_step(safe, scale_ok);
  }
  index(ctx, conveyor);
  dose(ctx);
  reset(ctx, conveyor);
  conveyor.commit();  // the last block on the conveyor this scan

  fault_edge(power.Error || index.Error || dose.Error);
  if (fault_edge.Q) {
    last_error = power.Error ? power.ErrorID : index.Error ? index.ErrorID : dose.ErrorID;
    step = Step::Fault;
  }
  if ((!safe || !scale_ok) && step != Step::WaitSafety && step != Step::Fault)
    step = Step::WaitSafety;
  if (step != Step::Index) index.Execute = false;
  if (step != Step::Fill) dose.Execute = false;
}

PLC_REGISTER_PROGRAM(FillingCell)

}  // namespace cell

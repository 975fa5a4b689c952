// The filling cell: a conveyor on a HIWIN E1 servo indexes containers under
// a filler; a Sartorius PR5510 doses each one (coarse/fine feed, adaptive
// preact); a NORD PROFIsafe module gates the conveyor: no drive enable while
// the safety module is passivated (QBAD) or its STO output (OSSD1) is off.
//
// The safety interlock here is a demonstration on simulated devices; the
// PROFIsafe F-host is not certified safety software.
#pragma once

#include "plc/fb/drive/mc_blocks.hpp"
#include "plc/fb/iec/iec.hpp"
#include "plc/fb/safety/nord_safe_io.hpp"
#include "plc/fb/weighing/batch_weigh.hpp"
#include "plc/fb/weighing/pr5510_device.hpp"
#include "plc/program.hpp"

namespace cell {

using namespace plc;

class FillingCell : public ProgramBase<FillingCell> {
 public:
  enum class Step : INT { WaitSafety = 0, Enable = 1, Index = 2, Fill = 3, Fault = 9 };

  // Parameters (settable with init:).
  BOOL run = true;
  LREAL pitch = 50000;            // conveyor index per container, control units
  LREAL index_velocity = 200000;  // CU/s
  REAL target_kg = 20.0F;

  // Devices and blocks.
  drive::DriveAxis conveyor;
  drive::MC_Power power;
  drive::MC_MoveRelative index;
  drive::MC_Reset reset;
  weighing::PR5510_Device scale;
  weighing::PR5510_BatchWeigh dose;
  safety::NORD_SAFE_IO guard;

  // State and results.
  Step step = Step::WaitSafety;
  DINT containers = 0;
  WORD last_error = 0;
  iec::R_TRIG fault_edge;

  FillingCell();
  void cycle(const ScanContext& ctx) override;

  PLC_REFLECT(run, pitch, index_velocity, target_kg, conveyor, power, index, reset, scale, dose,
              guard, step, containers, last_error, fault_edge)
  // The production count survives a power cut (a warm start); the batch
  // block keeps its learned preact and totals itself.
  PLC_RETAIN(containers)

 private:
  // cycle()'s sequence: the step Fill (most scans), every other step.
  void fill_step();
  void other_step(bool safe, bool scale_ok);
};

}  // namespace cell

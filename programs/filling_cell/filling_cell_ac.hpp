// The filling cell with an AC-drive conveyor: a Toyo VF66B (DNET66-Z,
// AC Drive profile assemblies 21/71) runs the belt at a fixed speed for a
// fixed time per container (an AC drive has no position loop: the index is
// time-based, as on a bench without a container sensor); the Sartorius
// PR5510 doses each container; the NORD PROFIsafe module gates the belt.
// Test bench for the DeviceNet scanner: programs/filling_cell/
// cell_vf66b_devicenet.yaml puts the drive and the scale on DeviceNet.
//
// The safety interlock is a demonstration on simulated devices; the
// PROFIsafe F-host is not certified safety software.
#pragma once

#include "plc/fb/acdrive/ac_drive.hpp"
#include "plc/fb/iec/iec.hpp"
#include "plc/fb/safety/nord_safe_io.hpp"
#include "plc/fb/weighing/batch_weigh.hpp"
#include "plc/fb/weighing/pr5510_device.hpp"
#include "plc/program.hpp"

namespace cell {

using namespace plc;

class FillingCellAc : public ProgramBase<FillingCellAc> {
 public:
  enum class Step : INT { WaitReady = 0, Index = 2, Settle = 3, Fill = 4, Fault = 9 };

  // Parameters (settable with init:).
  BOOL run = true;
  LREAL belt_speed = 900;  // r/min
  TIME index_time = std::chrono::milliseconds(800);
  REAL target_kg = 20.0F;
  TIME reset_pause = std::chrono::seconds(1);  // a drive fault still there after a reset: retry
  DINT reset_retries = 3;                      // ... this many times, then wait for the operator

  // Devices and blocks.
  acdrive::AcDrive conveyor;
  weighing::PR5510_Device scale;
  weighing::PR5510_BatchWeigh dose;
  safety::NORD_SAFE_IO guard;
  iec::TON index_timer;

  // State and results.
  Step step = Step::WaitReady;
  DINT containers = 0;
  WORD last_error = 0;
  iec::R_TRIG fault_edge;
  iec::TON reset_wait;      // the fault outlasts the reset pulse
  DINT reset_attempts = 0;  // retries of the fault reset since the fault

  FillingCellAc();
  void cycle(const ScanContext& ctx) override;

  PLC_REFLECT(run, belt_speed, index_time, target_kg, reset_pause, reset_retries, conveyor, scale,
              dose, guard, index_timer, step, containers, last_error, fault_edge, reset_wait,
              reset_attempts)
  PLC_RETAIN(containers)
};

}  // namespace cell

// What both filling cells (FillingCell: PROFIdrive conveyor; FillingCellAc:
// AC-drive conveyor) set up the same way: the NORD module's F-parameters
// and the PR5510's dosing. One place, so that the two cells cannot drift.
#pragma once

#include "plc/fb/safety/nord_safe_io.hpp"
#include "plc/fb/weighing/batch_weigh.hpp"
#include "plc/fb/weighing/pr5510_device.hpp"

namespace cell {

inline void set_up_filling_station(plc::safety::NORD_SAFE_IO& guard,
                                   plc::weighing::PR5510_Device& scale,
                                   plc::weighing::PR5510_BatchWeigh& dose, plc::REAL target_kg) {
  scale.port.set_device_name("scale");
  guard.FMOD.port.set_device_name("safety");
  guard.FMOD.F_Dest_Add = 1;  // the module's DIP address (the cell files' dip_address)
  guard.FMOD.F_Source_Add = 10;
  guard.FMOD.F_WD_Time = 100;
  dose.Device = &scale;
  dose.TargetWeight = target_kg;
  dose.FineSwitchPoint = 2.0F;
  dose.Preact = 0.15F;
  dose.TolPlus = 0.05F;
  dose.TolMinus = 0.05F;
}

}  // namespace cell

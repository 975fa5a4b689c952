// PR5510_Command: one W[7] command (Set Zero, Set Tare, Reset Tare, Start
// and End analog test, Reset Power-Fail; spec §3.3) as a rising edge held
// at least 40 ms, pulsed by the shared PR5510_Device. Execute-style
// (PLCopen). Done when the device has taken the edge, Cmd_Busy is off
// without Cmd_Error and the status shows the result (spec §5.5 feedback:
// Tare Active, Test Active, Power Fail); Error with ErrorID 16#81nn (nn =
// device error: 31 no standstill, 33 negative tare in W&M, 47 zero outside
// range; spec §5.3), or 16#8015 when the result never shows.
#pragma once

#include "plc/fb/weighing/pr5510_device.hpp"

namespace plc::weighing {

class PR5510_Command {
 public:
  PR5510_Device* Device = nullptr;
  BOOL Execute{};
  CommandBit Command = CommandBit::SetTare;

  BOOL Done{};
  BOOL Busy{};
  BOOL Error{};
  WORD ErrorID{};

  PLC_REFLECT(Execute, Command, Done, Busy, Error, ErrorID,
              /* internal state */ slot_, prev_execute_)
  PLC_INTERNAL(slot_, prev_execute_)

  void operator()(const ScanContext& ctx);

 private:
  int slot_ = PR5510_Device::kNoSlot;
  bool prev_execute_ = false;
};

}  // namespace plc::weighing

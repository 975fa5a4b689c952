// PR5510_WriteValue: one write through the write window with the
// Write_Active handshake (spec §3.6 / §7.2 Write), run by the shared
// PR5510_Device. Execute-style (PLCopen): inputs latched on the rising edge
// of Execute; Done or Error held while Execute stays TRUE, or one scan.
// A device Cmd_Error gives ErrorID 16#81nn with nn = the device error
// number (spec §5.3 error table), read back from code 4.
#pragma once

#include "plc/fb/weighing/pr5510_device.hpp"

namespace plc::weighing {

class PR5510_WriteValue {
 public:
  PR5510_Device* Device = nullptr;
  BOOL Execute{};
  USINT Code{};      // write code, spec §5.4 (0x70..0x75 firmware, application areas)
  DINT Value{};      // sent as DINT (§4.1) ...
  REAL ValueReal{};  // ... or as REAL (§4.2) when UseReal
  BOOL UseReal{};

  BOOL Done{};
  BOOL Busy{};
  BOOL Error{};
  WORD ErrorID{};

  PLC_REFLECT(Execute, Code, Value, ValueReal, UseReal, Done, Busy, Error, ErrorID,
              /* internal state */ slot_, prev_execute_)
  PLC_INTERNAL(slot_, prev_execute_)

  void operator()(const ScanContext& ctx);

 private:
  int slot_ = PR5510_Device::kNoSlot;
  bool prev_execute_ = false;
};

}  // namespace plc::weighing

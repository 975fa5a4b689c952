// PR5510_ReadValue: live reading of one read code through the shared read
// window (spec §3.5 / §7.2 Read). Enable-style: while Enable is TRUE the
// block keeps requesting Code; Value follows the device every 20 ms while
// the block holds the window. When other blocks share the window it takes
// turns (see PR5510_Device); between turns Value keeps the last reading and
// Valid stays TRUE. Errors (no device, offline, echo timeout, undefined
// code) are held until Enable goes FALSE.
#pragma once

#include "plc/fb/weighing/pr5510_device.hpp"

namespace plc::weighing {

class PR5510_ReadValue {
 public:
  PR5510_Device* Device = nullptr;  // the shared device (VAR_IN_OUT style)
  BOOL Enable{};
  USINT Code{};  // read code, spec §5.2 (0x04..0x0E firmware, 0x18..0xC7 application)

  BOOL Valid{};
  BOOL Busy{};
  BOOL Error{};
  WORD ErrorID{};
  DINT Value{};      // the 4 bytes as DINT (§4.1)
  REAL ValueReal{};  // the same 4 bytes as REAL (§4.2)
  DWORD Raw{};       // the same 4 bytes unsigned (packed codes 4 and 5)
  UDINT Updates{};   // scans in which Value was taken from the window

  PLC_REFLECT(Enable, Code, Valid, Busy, Error, ErrorID, Value, ValueReal, Raw, Updates,
              /* internal state */ slot_, last_code_)
  PLC_INTERNAL(slot_, last_code_)

  void operator()(const ScanContext& ctx);

 private:
  void fail(std::uint16_t id);
  int slot_ = PR5510_Device::kNoSlot;
  USINT last_code_{};
};

}  // namespace plc::weighing

// PR5510_Status: the 24 status bits of read bytes 5-7 (spec §3.4), named.
// They are always current and need no handshake; Valid is FALSE while the
// device is offline (the bits then keep their last values).
#pragma once

#include "plc/fb/weighing/pr5510_device.hpp"

namespace plc::weighing {

class PR5510_Status {
 public:
  PR5510_Device* Device = nullptr;

  BOOL Valid{};
  // R[5]
  BOOL Limit1{}, Limit2{}, Limit3{}, Out1{}, Out2{}, Out3{}, PowerFail{}, WriteActive{};
  // R[6]
  BOOL TestActive{}, CalChanged{}, TareActive{}, Inp1{}, Inp2{}, Inp3{}, CmdError{}, CmdBusy{};
  // R[7]
  BOOL AduError{}, AboveFsd{}, Overload{}, BelowZero{}, CenterZero{}, InsideZsr{}, StandStill{},
      Dimmed{};

  PLC_REFLECT(Valid, Limit1, Limit2, Limit3, Out1, Out2, Out3, PowerFail, WriteActive, TestActive,
              CalChanged, TareActive, Inp1, Inp2, Inp3, CmdError, CmdBusy, AduError, AboveFsd,
              Overload, BelowZero, CenterZero, InsideZsr, StandStill, Dimmed)

  void operator()(const ScanContext& ctx);
};

}  // namespace plc::weighing

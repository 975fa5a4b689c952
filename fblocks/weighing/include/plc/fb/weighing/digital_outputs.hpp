// PR5510_DigitalOutputs: the PR5510's digital outputs 1-3 (W[6] bits 0-2,
// level; [INFERRED] spec §3.3) and their read-back Out 1-3 (R[5] bits 3-5).
// Drive each output from one block only (PR5510_Device arbitration).
#pragma once

#include "plc/fb/weighing/pr5510_device.hpp"

namespace plc::weighing {

class PR5510_DigitalOutputs {
 public:
  PR5510_Device* Device = nullptr;
  BOOL Enable{};  // FALSE: the block leaves the outputs alone
  BOOL Out1{}, Out2{}, Out3{};

  BOOL Valid{};  // device online, read-back below is current
  BOOL Out1State{}, Out2State{}, Out3State{};

  PLC_REFLECT(Enable, Out1, Out2, Out3, Valid, Out1State, Out2State, Out3State)

  void operator()(const ScanContext& ctx);
};

}  // namespace plc::weighing

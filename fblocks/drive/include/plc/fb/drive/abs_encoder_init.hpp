// AbsEncoderInit: the absolute-encoder initialisation of spec §7.10 (E1
// manual §6.9, method 2) as one Execute block:
//   1. refuse while the axis is enabled (ZSW1.2), unless AllowDisable: then
//      take power away (InhibitPower -> OFF1) and wait until the pulses are
//      off;
//   2. write 3200h = 1 (Int32);
//   3. read 3200h until it is 4 (2 = running; 16 = refused, motor enabled;
//      32 = failed);
//   4. write 3215h = 1 (Int16): the drive resets, stops answering, and comes
//      back in S1; the block waits for it to go offline and online again and
//      then clears the axis' communication error (an expected outage).
//      The restart stays inhibited (DriveAxis::RestartInhibit): an enable
//      held through the procedure powers the drive again only after
//      MC_Reset / AckError (the multi-turn reference just changed), or,
//      with RequireEnableEdgeAfterReset, after a new Enable edge.
// Status shows the last value read from 3200h (0, 1, 2, 4, 16, 32) and Step
// the procedure step (0 idle, 1 disable, 2 write, 3 poll, 4 reset, 5 wait
// for the drive, 6 done).
// ErrorID: 16#9001 refused (axis enabled), 16#9002 disable timeout, 16#9004
// timeout while 3200h is 2 (running), 16#9005 timeout before 3200h reached
// 2 or 4, 16#9006 drive not back after the reset, 16#9016 drive refused
// (16), 16#9032 drive failed (32), plus the parameter-access codes
// 16#81xx/82xx/83xx of SinaPara. Each waiting step has the full Timeout.
#pragma once

#include "plc/fb/drive/drive_axis.hpp"
#include "plc/fb/drive/param_client.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::drive {

inline constexpr std::uint16_t kPnuAbsEncoderInit = 0x3200;
inline constexpr std::uint16_t kPnuResetDrive = 0x3215;

struct AbsEncoderInit {
  BOOL Execute{};
  BOOL AllowDisable{};
  TIME Timeout = std::chrono::seconds(10);
  UINT RecordIndex = kParamRecordIndex;
  BOOL Done{};
  BOOL Busy{};
  BOOL Error{};
  WORD ErrorID{};
  INT Status{};
  INT Step{};

  void operator()(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(Execute, AllowDisable, Timeout, RecordIndex, Done, Busy, Error, ErrorID, Status, Step,
              /* internal state */ client_, prev_execute_, seen_running_, seen_offline_, t0_)
  // Step too: the procedure runs on it.
  PLC_INTERNAL(Step, client_, prev_execute_, seen_running_, seen_offline_, t0_)

  ParamClient client_;
  bool prev_execute_ = false;
  bool seen_running_ = false, seen_offline_ = false;
  TIME t0_{};
};

}  // namespace plc::drive

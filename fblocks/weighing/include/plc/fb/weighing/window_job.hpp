// The PLCopen Execute handling shared by the one-shot window blocks
// (PR5510_WriteValue, PR5510_Command): act on the rising edge of Execute,
// hold Done/Error while Execute stays TRUE (else for one scan), check the
// device before starting (with the ErrorIDs of error_ids.hpp), and collect
// the device block's answer.
#pragma once

#include <cstdint>
#include <utility>

#include "plc/fb/weighing/error_ids.hpp"
#include "plc/fb/weighing/pr5510_device.hpp"

namespace plc::weighing {

// The Execute interface of a block, by reference.
struct ExecuteSignals {
  BOOL& Execute;
  BOOL& Done;
  BOOL& Busy;
  BOOL& Error;
  WORD& ErrorID;
  bool& prev_execute;
};

enum class JobResult : std::uint8_t { Pending, Done, Error };

// start(): hand the job to the device (called once, when every check
// passed). poll(): {Pending|Done|Error, error id}; it acknowledges the job
// on the device when the job is finished.
template <class Start, class Poll>
void run_window_job(ExecuteSignals s, PR5510_Device* device, int& slot, bool code_ok, Start&& start,
                    Poll&& poll) {
  const bool rising = s.Execute && !s.prev_execute;
  s.prev_execute = s.Execute;
  if ((s.Done || s.Error) && !s.Execute) {
    s.Done = s.Error = false;
    s.ErrorID = error_id::kNone;
  }
  if (rising && !s.Busy) {
    s.Done = s.Error = false;
    s.ErrorID = error_id::kNone;
    std::uint16_t err = error_id::kNone;
    if (device == nullptr) {
      err = error_id::kNoDevice;
    } else {
      if (slot == PR5510_Device::kNoSlot) slot = device->attach();
      if (slot == PR5510_Device::kNoSlot) {
        err = error_id::kTooManyClients;
      } else if (!code_ok) {
        err = error_id::kInvalidCode;
      } else if (!device->Online) {
        err = error_id::kDeviceOffline;
      } else {
        start();
        s.Busy = true;
      }
    }
    if (err != error_id::kNone) {
      s.Error = true;
      s.ErrorID = err;
    }
  }
  if (!s.Busy) return;
  if (device == nullptr) {  // Busy set from outside (debugger, HMI) with no device
    s.Busy = false;
    s.Error = true;
    s.ErrorID = error_id::kNoDevice;
    return;
  }
  const std::pair<JobResult, std::uint16_t> r = poll();
  if (r.first == JobResult::Done) {
    s.Busy = false;
    s.Done = true;
  } else if (r.first == JobResult::Error) {
    s.Busy = false;
    s.Error = true;
    s.ErrorID = r.second;
  }
}

}  // namespace plc::weighing

// ErrorID values of the AC drive blocks (WORD), also in
// fblocks/acdrive/README.md.
//
// | value   | name               | meaning |
// |---------|--------------------|---------|
// | 16#0000 | kNone              | no error |
// | 16#8001 | kOffline           | device not online (port not bound, connection lost, not
// answering) | | 16#8002 | kConfig            | OutputInstance/InputInstance not a §7.2 instance,
// or the port's sizes do not match them | | 16#8003 | kSpeedRange        | SpeedRef not finite or
// beyond the INT range at SpeedScale (or beyond 32767 counts of Speed Reference2); the last valid
// value stays on the wire | | 16#8004 | kDriveFault        | the drive reports Faulted; protect
// code unknown (70/71) | | 16#84nn | kDriveFaultBase+nn | the drive reports protect code nn (1..32,
// Table 6.4; 120..132, 140) | | 16#85gg | kErrorResponse+gg  | explicit Error Response, general
// status gg (§11.1); AdditionalCode output | | 16#83xx | kRecordRefused+xx  | record path refused
// the request, xx = plc::io::RecordError | | 16#8201 | kBadInput          | AcDriveAttribute:
// Service/Length/Value invalid (not sent) | | 16#8202 | kBusy              | AcDriveAttribute: the
// previous request is still in flight | | 16#8203 | kTimeout           | AcDriveAttribute: no
// answer within Timeout |
#pragma once

#include <cstdint>

namespace plc::acdrive::error_id {

inline constexpr std::uint16_t kNone = 0x0000;
inline constexpr std::uint16_t kOffline = 0x8001;
inline constexpr std::uint16_t kConfig = 0x8002;
inline constexpr std::uint16_t kSpeedRange = 0x8003;
inline constexpr std::uint16_t kDriveFault = 0x8004;
inline constexpr std::uint16_t kDriveFaultBase = 0x8400;
inline constexpr std::uint16_t kErrorResponse = 0x8500;
inline constexpr std::uint16_t kRecordRefused = 0x8300;
inline constexpr std::uint16_t kBadInput = 0x8201;
inline constexpr std::uint16_t kBusy = 0x8202;
inline constexpr std::uint16_t kTimeout = 0x8203;

constexpr std::uint16_t drive_fault(std::uint8_t protect_code) {
  return protect_code == 0 ? kDriveFault
                           : static_cast<std::uint16_t>(kDriveFaultBase + protect_code);
}

}  // namespace plc::acdrive::error_id

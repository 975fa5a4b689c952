// The PR5510 fieldbus windows (PR1721/31 Profibus-DP, PR1721/34 DeviceNet):
// byte positions, bit positions and codes, exactly as the manual's tables give
// them (spec shared/specs/sartorius-pr1721.md, "§" = section of that file).
// Shared by the function blocks (PLC side) and the simulated PR5510.
#pragma once

#include <cstddef>
#include <cstdint>

namespace plc::weighing {

// §3.2: the 8-byte layout is the only one the manual defines.
inline constexpr std::size_t kWindowSize = 8;
// §0: the PR5510 refreshes the fieldbus data every 20 ms.
inline constexpr std::int64_t kDeviceCycleMs = 20;
// §3.3: a W[7] command flag must stay ON at least 40 ms.
inline constexpr std::int64_t kCommandHoldMinMs = 40;

// ---- write window, master -> PR5510 (§3.3) ----
namespace w {
inline constexpr std::size_t kValue = 0;             // bytes 0..3: Write_Value
inline constexpr std::size_t kReadValueSelect = 4;   // Read_Value_Select
inline constexpr std::size_t kWriteValueSelect = 5;  // Write_Value_Select
inline constexpr std::size_t kOutputs = 6;           // digital outputs (level)
inline constexpr std::size_t kCommands = 7;          // rising-edge commands
}  // namespace w

// W[6] bits 0..2 (§3.3).
enum class OutputBit : std::uint8_t { Out1 = 0, Out2 = 1, Out3 = 2 };

// W[7] bits 0..5 (§3.3): each acts on its 0->1 edge.
enum class CommandBit : std::uint8_t {
  SetZero = 0,
  SetTare = 1,
  ResTare = 2,
  SetTest = 3,
  ResTest = 4,
  ResPower = 5,
};
inline constexpr std::uint8_t kCommandBitCount = 6;

// ---- read window, PR5510 -> master (§3.4) ----
namespace r {
inline constexpr std::size_t kValue = 0;              // bytes 0..3: Read_Value
inline constexpr std::size_t kReadValueSelected = 4;  // echo of W[4]
inline constexpr std::size_t kStatus = 5;             // "status" / system bits
inline constexpr std::size_t kCommand = 6;            // "command" bits
inline constexpr std::size_t kWeighing = 7;           // "weighing status" bits
}  // namespace r

// R[5] (§3.4, read byte 5 table).
namespace r5 {
inline constexpr unsigned kLimit1 = 0, kLimit2 = 1, kLimit3 = 2;
inline constexpr unsigned kOut1 = 3, kOut2 = 4, kOut3 = 5;
inline constexpr unsigned kPowerFail = 6;
inline constexpr unsigned kWriteActive = 7;
}  // namespace r5
// R[6] (§3.4, read byte 6 table).
namespace r6 {
inline constexpr unsigned kTestActive = 0;
inline constexpr unsigned kCalChanged = 1;
inline constexpr unsigned kTareActive = 2;
inline constexpr unsigned kInp1 = 3, kInp2 = 4, kInp3 = 5;
inline constexpr unsigned kCmdError = 6;
inline constexpr unsigned kCmdBusy = 7;
}  // namespace r6
// R[7] (§3.4, read byte 7 table).
namespace r7 {
inline constexpr unsigned kAduError = 0;
inline constexpr unsigned kAboveFsd = 1;
inline constexpr unsigned kOverload = 2;
inline constexpr unsigned kBelowZero = 3;
inline constexpr unsigned kCenterZero = 4;
inline constexpr unsigned kInsideZsr = 5;
inline constexpr unsigned kStandStill = 6;
inline constexpr unsigned kDimmed = 7;
}  // namespace r7

// Read-data request codes, W[4] / R[4] (§5.2).
enum class ReadCode : std::uint8_t {
  None = 0x00,          // 0..3 reserved
  Format = 0x04,        // decimals / unit / division / last error (packed, §5.3)
  ModelVersion = 0x05,  // model / version (packed, §5.3; missing from the list, [AMBIG] 6)
  Gross = 0x08,
  Net = 0x09,
  Tare = 0x0A,
  Gross100 = 0x0C,   // gross x 100 ([INFERRED]: two extra digits, DINT)
  FullScale = 0x0E,  // reading it clears Cal_Changed
};
// Application area of the read codes (§5.1/§5.2: 24..199; [AMBIG] 5 says
// §2 writes 20, the tables 24: we follow the tables).
inline constexpr std::uint8_t kReadAppFirst = 0x18, kReadAppLast = 0xC7;

// Write-data codes, W[5] (§5.4).
enum class WriteCode : std::uint8_t {
  None = 0x00,     // no request: part of the handshake
  SetZero = 0x70,  // [INFERRED] (blank in the manual, [AMBIG] 7)
  SetTare = 0x71,
  ResetTare = 0x72,
  StartTest = 0x73,
  EndTest = 0x74,
  ResetPowerFail = 0x75,
  Limit1On = 0x18,  // the manual's only application example
};
// Application areas of the write codes (§5.1).
inline constexpr std::uint8_t kWriteAppLowFirst = 0x18, kWriteAppLowLast = 0x39;
inline constexpr std::uint8_t kWriteAppHighFirst = 0x78, kWriteAppHighLast = 0xC7;

// Is `c` a write code the manual assigns (firmware command or application)?
constexpr bool is_defined_write_code(std::uint8_t c) {
  return (c >= 0x70 && c <= 0x75) || (c >= kWriteAppLowFirst && c <= kWriteAppLowLast) ||
         (c >= kWriteAppHighFirst && c <= kWriteAppHighLast);
}
// Is `c` a read code the manual assigns (firmware or application)?
constexpr bool is_defined_read_code(std::uint8_t c) {
  return c == 0x04 || c == 0x05 || c == 0x08 || c == 0x09 || c == 0x0A || c == 0x0C || c == 0x0E ||
         (c >= kReadAppFirst && c <= kReadAppLast);
}

// Unit byte of code 4 (§5.3).
enum class Unit : std::uint8_t { g = 0x02, kg = 0x03, t = 0x04, lb = 0x05 };

// Device error numbers, "last displayed error" of code 4 (§5.3 error table).
namespace device_error {
inline constexpr std::uint8_t kNone = 0;
inline constexpr std::uint8_t kStandstillTimeout = 31;
inline constexpr std::uint8_t kTareNegativeWm = 33;
inline constexpr std::uint8_t kOverFullScale = 35;
inline constexpr std::uint8_t kCalSwitchLocked = 40;
inline constexpr std::uint8_t kNotInCalMode = 41;
inline constexpr std::uint8_t kCalInProgress = 42;
inline constexpr std::uint8_t kTaringActive = 46;
inline constexpr std::uint8_t kZeroOutsideRange = 47;
}  // namespace device_error

}  // namespace plc::weighing

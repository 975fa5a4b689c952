// PROFIsafe V2 control byte (F-host -> F-device) and status byte (F-device ->
// F-host). The NORD manual does not define them (spec nord-profisafe.md §2.5);
// these are the [SPEC] bit positions of the spec and softplc-anchors.md §4.4,
// TO BE VERIFIED AGAINST IEC 61784-3-3. Real traffic (profisafe-wire-
// vectors.md) confirms status bits 5 (Toggle_d, alternating) and 6
// (cons_nr_R, set in the telegram after a reset); it cannot settle the
// control byte, bit 7 included.
#pragma once

#include <cstdint>

namespace plc::safety {

namespace cb {                                        // control byte, host -> device
inline constexpr std::uint8_t kIparEn = 1u << 0;      // i-parameter assignment deblocked
inline constexpr std::uint8_t kOaReq = 1u << 1;       // operator acknowledge request
inline constexpr std::uint8_t kRConsNr = 1u << 2;     // reset the consecutive number
inline constexpr std::uint8_t kUseTo2 = 1u << 3;      // reserved, sent as 0
inline constexpr std::uint8_t kActivateFv = 1u << 4;  // device must use fail-safe values
inline constexpr std::uint8_t kToggleH = 1u << 5;     // host toggle bit
}  // namespace cb

namespace sb {                                         // status byte, device -> host
inline constexpr std::uint8_t kIparOk = 1u << 0;       // new i-parameters assigned
inline constexpr std::uint8_t kDeviceFault = 1u << 1;  // NORD "Fault"
inline constexpr std::uint8_t kCeCrc = 1u << 2;        // device saw a CRC2 / cons-nr error
inline constexpr std::uint8_t kWdTimeout = 1u << 3;    // device watchdog expired
inline constexpr std::uint8_t kFvActivated = 1u << 4;  // device outputs fail-safe values
inline constexpr std::uint8_t kToggleD = 1u << 5;      // device echo of Toggle_h
inline constexpr std::uint8_t kConsNrR = 1u << 6;      // consecutive number was reset
}  // namespace sb

}  // namespace plc::safety

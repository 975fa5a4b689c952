// Fault classes the F-host tells apart, as bits of the F-module's DIAG byte.
//
// Our own layout (the Siemens DIAG bit layout is not in our references, see
// softplc-anchors.md §4.4); bits 0-6 are latched from the fault until the
// module is reintegrated, so a test or an operator can see which class
// tripped; bit 7 follows the device's current diagnosis.
#pragma once

#include <cstdint>

namespace plc::safety::diag {

inline constexpr std::uint8_t kHostCrc = 1u << 0;    // CRC2 / cons-nr error seen by the host
inline constexpr std::uint8_t kHostWd = 1u << 1;     // host watchdog F_WD_Time expired
inline constexpr std::uint8_t kDevCeCrc = 1u << 2;   // device reported CE_CRC
inline constexpr std::uint8_t kDevWd = 1u << 3;      // device reported WD_timeout
inline constexpr std::uint8_t kDevFault = 1u << 4;   // device reported Device_Fault
inline constexpr std::uint8_t kFParError = 1u << 5;  // F-parameter record refused
inline constexpr std::uint8_t kNoLink = 1u << 6;     // port unbound / record not reachable
// Not latched: the device reports a 57xx code now (its P841, read by record),
// also without module passivation (channel passivation, report-only
// violations with P801 = 1). DIAG_CODE holds the code.
inline constexpr std::uint8_t kDevCode = 1u << 7;

}  // namespace plc::safety::diag

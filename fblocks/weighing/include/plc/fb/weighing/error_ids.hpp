// ErrorID values of the weighing blocks (WORD). 16#80xx: window protocol and
// communication; 16#81nn: the device reported error number nn (the "last
// displayed error" of read code 4, spec §5.3 error table: 31, 33, 35, 47,
// ...); 16#82xx: batch weighing.
#pragma once

#include <cstdint>

namespace plc::weighing::error_id {

inline constexpr std::uint16_t kNone = 0x0000;
inline constexpr std::uint16_t kNoDevice = 0x8001;        // Device input not set
inline constexpr std::uint16_t kTooManyClients = 0x8002;  // all arbitration slots taken
inline constexpr std::uint16_t kDeviceOffline = 0x8003;   // port not bound or not Online
inline constexpr std::uint16_t kInvalidCode = 0x8004;     // code outside the manual's tables
inline constexpr std::uint16_t kNoJob = 0x8005;  // Busy set from outside: no slot or nothing to do
inline constexpr std::uint16_t kReadEchoTimeout = 0x8010;      // R[4] never echoed the code
inline constexpr std::uint16_t kWriteBusyTimeout = 0x8011;     // Write_Active stuck at 1
inline constexpr std::uint16_t kWriteAckTimeout = 0x8012;      // Write_Active never rose
inline constexpr std::uint16_t kWriteReleaseTimeout = 0x8013;  // Write_Active never fell
inline constexpr std::uint16_t kCommandBusyTimeout = 0x8014;   // Cmd_Busy stayed on
inline constexpr std::uint16_t kCommandNoEffect = 0x8015;      // status never showed the result
inline constexpr std::uint16_t kDeviceErrorBase = 0x8100;      // + device error number
inline constexpr std::uint16_t kDeviceErrorUnknown = 0x81FF;   // Cmd_Error, number unreadable

inline constexpr std::uint16_t kInvalidParameter = 0x8201;
inline constexpr std::uint16_t kFillTimeout = 0x8202;    // MaxFillTime exceeded
inline constexpr std::uint16_t kSettleTimeout = 0x8203;  // no standstill in MaxSettleTime
inline constexpr std::uint16_t kWeightInvalid = 0x8204;  // Adu Error / Over-load / above FSD
inline constexpr std::uint16_t kDischargeTimeout = 0x8205;
inline constexpr std::uint16_t kOverWeight = 0x8206;   // out of tolerance, too heavy
inline constexpr std::uint16_t kUnderWeight = 0x8207;  // out of tolerance, too light
inline constexpr std::uint16_t kNotReady = 0x8208;     // device format (code 4) unknown
inline constexpr std::uint16_t kBelowZero = 0x8209;    // weight clearly below zero (R[7].3/.5)

constexpr std::uint16_t device_error(std::uint8_t n) {
  return n == 0 ? kDeviceErrorUnknown : static_cast<std::uint16_t>(kDeviceErrorBase + n);
}

}  // namespace plc::weighing::error_id

// VF66B protection (fault) codes, toyo-vf66-devicenet.md §7.8 (Table 6.4),
// and the 32-bit fault field of the extended input assemblies (§7.6): bit
// n-1 of the field is fault code n; when several are active the lowest code
// is the ProtectErrorCode (instance 140, §7.7).
#pragma once

#include <cstdint>

namespace plc::acdrive {

enum class ProtectCode : std::uint8_t {
  None = 0,
  Overcurrent = 1,
  Igbt = 2,
  // 3 and 4 are blank in Table 6.4 and in the bit field
  GacError = 5,  // bit-field name: gate board error
  DcOvervoltage = 6,
  Overload = 7,
  DcctError = 8,  // bit-field name: current sensor error
  StartStall = 9,
  Overspeed = 10,
  Overfrequency = 11,
  Undervoltage = 12,
  Overtorque = 13,
  UnitOverheat = 14,
  MemoryError = 15,
  OptionError = 16,
  SensorlessStartError = 17,
  CommunicationTimeout = 18,
  SpeedControlError = 19,
  MotorOverheat = 20,
  ChargingResistorOverheat = 21,
  FclOperation = 22,
  SettingError = 23,
  PhaseLoss = 24,
  CpuAbnormal = 25,
  FanFailure = 26,
  PgError = 27,
  SensorError = 28,
  ExternalFault1 = 29,
  ExternalFault2 = 30,
  ExternalFault3 = 31,
  ExternalFault4 = 32,
};

inline constexpr std::uint8_t kMaxProtectCode = 32;

// True for the codes Table 6.4 defines (1, 2, 5..32).
constexpr bool is_defined_protect_code(unsigned code) {
  return code >= 1 && code <= kMaxProtectCode && code != 3 && code != 4;
}
// Table 6.4 text ("No fault / protection" for 0, "" for 3, 4 and > 32).
const char* protect_code_text(unsigned code);

constexpr std::uint32_t fault_bit(unsigned code) {
  return code >= 1 && code <= kMaxProtectCode ? (std::uint32_t{1} << (code - 1)) : 0;
}
// The lowest active code of a fault field (§7.8: the lowest number wins); 0
// when none is set.
constexpr std::uint8_t lowest_protect_code(std::uint32_t faults) {
  for (unsigned n = 1; n <= kMaxProtectCode; ++n)
    if (faults & fault_bit(n)) return static_cast<std::uint8_t>(n);
  return 0;
}

}  // namespace plc::acdrive

// NORD PROFIsafe error codes (P841/P842), spec nord-profisafe.md §5.5.
#pragma once

#include <cstdint>

namespace plc::safety::nord::err {

// F-parameter errors (q unless noted)
inline constexpr std::uint16_t kDestMismatch = 5711;
inline constexpr std::uint16_t kDestInvalid = 5712;
inline constexpr std::uint16_t kSourceInvalid = 5713;
inline constexpr std::uint16_t kWatchdogZero = 5714;
inline constexpr std::uint16_t kSilTooHigh = 5715;
inline constexpr std::uint16_t kParVersion = 5716;
inline constexpr std::uint16_t kParCrc = 5717;
inline constexpr std::uint16_t kParGeneral = 5718;
inline constexpr std::uint16_t kIparCrc = 5719;
inline constexpr std::uint16_t kCrcLength = 5721;
inline constexpr std::uint16_t kParTelegram = 5725;  // f
inline constexpr std::uint16_t kDipRead = 5726;      // f
// I/O errors (q)
inline constexpr std::uint16_t kDiscrepancy = 5731;
inline constexpr std::uint16_t kOutput1 = 5732;
inline constexpr std::uint16_t kOutput2 = 5733;
inline constexpr std::uint16_t kOutput3 = 5734;
inline constexpr std::uint16_t kClock1 = 5735;
inline constexpr std::uint16_t kClock2 = 5736;
inline constexpr std::uint16_t kInput1Diag = 5737;
inline constexpr std::uint16_t kInput2Diag = 5738;
inline constexpr std::uint16_t kSo1NotEnabled = 5741;
inline constexpr std::uint16_t kSo2NotEnabled = 5742;
inline constexpr std::uint16_t kSo3NotEnabled = 5743;
inline constexpr std::uint16_t kSi1NotEnabled = 5746;
inline constexpr std::uint16_t kSi2NotEnabled = 5747;
// i-parameter range errors (f)
inline constexpr std::uint16_t kP802Range = 5748;
inline constexpr std::uint16_t kP804Range = 5749;
inline constexpr std::uint16_t kP805Range = 5751;
inline constexpr std::uint16_t kP800Range = 5752;
inline constexpr std::uint16_t kP803Range = 5753;
inline constexpr std::uint16_t kP801Range = 5754;
inline constexpr std::uint16_t kEncoderParRange = 5755;
inline constexpr std::uint16_t kSls = 5756;  // f/q, then 5757 SSR, 5758 SDI-P, 5759 SDI-N
inline constexpr std::uint16_t kSsr = 5757;
inline constexpr std::uint16_t kSdiP = 5758;
inline constexpr std::uint16_t kSdiN = 5759;
inline constexpr std::uint16_t kSos = 5761;  // 5760 is not defined
inline constexpr std::uint16_t kP821Range = 5762;
inline constexpr std::uint16_t kP822Range = 5763;
inline constexpr std::uint16_t kP823Range = 5764;
inline constexpr std::uint16_t kP824Range = 5765;
inline constexpr std::uint16_t kLimitFrequency = 5766;
// system / encoder
inline constexpr std::uint16_t kTemperature = 5771;  // f
inline constexpr std::uint16_t kEncoder = 5772;      // q
inline constexpr std::uint16_t kSupply = 5774;       // f
inline constexpr std::uint16_t kSpeedDiff = 5776;    // f
// safety-function violations (q, reintegration >= 10 s after the error)
inline constexpr std::uint16_t kSlsViolated = 5781;
inline constexpr std::uint16_t kSsrViolated = 5782;
inline constexpr std::uint16_t kSdiPViolated = 5783;
inline constexpr std::uint16_t kSdiNViolated = 5784;
inline constexpr std::uint16_t kSosViolated = 5785;
inline constexpr std::uint16_t kSystemError = 5791;     // f
inline constexpr std::uint16_t kSystemErrorMax = 5792;  // f, permanent

}  // namespace plc::safety::nord::err

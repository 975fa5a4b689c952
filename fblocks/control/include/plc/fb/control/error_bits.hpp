// PID_Compact's ErrorBits: the codes are the PID_Compact manual's (Siemens
// A5E35300227, "ErrorBits parameter"), one bit each, added when several
// are pending. Only those this block can raise are defined; where our
// meaning is narrower or wider than the manual's it says so.
#pragma once

#include <cstdint>

namespace plc::control::error_bits {

// Input outside [InputLowerLimit, InputUpperLimit]. Automatic mode goes on
// with ActivateRecoverMode (as in the manual).
inline constexpr std::uint32_t kInputOutOfLimits = 0x0000'0001;
// Input_PER outside the S7 analog range -32512..32511 (overflow 32767 /
// underflow -32768 of a broken wire or an overdriven module).
inline constexpr std::uint32_t kInputPerInvalid = 0x0000'0002;
// Invalid controller parameters [reading: the manual raises 0100h for
// parameters from a failed fine tuning; we raise it for any invalid
// Gain, Ti, Td, TdFiltRatio, weighting or limit pair, which a program can
// write at any time]: the block goes to the error reaction.
inline constexpr std::uint32_t kInvalidParameters = 0x0000'0100;
// Input is not a number (NaN or infinite).
inline constexpr std::uint32_t kInputInvalid = 0x0000'0200;
// The output came out non-finite.
inline constexpr std::uint32_t kOutputFailed = 0x0000'0400;
// Sampling time error [reading: the manual means "not called within the
// cyclic interrupt's time"; we raise it when no time passed since the last
// call (the block called twice in one scan), where no rate can be formed].
inline constexpr std::uint32_t kSamplingTime = 0x0000'0800;
// Setpoint is not a number.
inline constexpr std::uint32_t kSetpointInvalid = 0x0000'1000;
// ManualValue is not a number (manual mode then outputs SubstituteOutput).
inline constexpr std::uint32_t kManualValueInvalid = 0x0001'0000;
// SubstituteOutput is not a number (the output low limit is used instead).
inline constexpr std::uint32_t kSubstituteOutputInvalid = 0x0002'0000;
// Disturbance is not a number (treated as 0).
inline constexpr std::uint32_t kDisturbanceInvalid = 0x0004'0000;

}  // namespace plc::control::error_bits

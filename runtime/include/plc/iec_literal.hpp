// IEC 61131-3 literals: parsing (config, debugger commands) and printing
// (watch, trace, --list-vars) in IEC notation: T#1s500ms, 16#047F, TRUE.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "plc/types.hpp"

namespace plc {

// "T#1s500ms", "TIME#-2m", "t#1.5s", "20ms", "1h2m3s4ms5us6ns". Units d h m s
// ms us ns; a bare number is not a time (units are required).
std::optional<TIME> parse_iec_time(std::string_view s);
// Why parse_iec_time(s) fails: not a TIME literal, or beyond the TIME range
// (about 292 years either way); "" when it is a TIME.
std::string iec_time_error(std::string_view s);
// "123", "-5", "16#FF", "2#1010_0101", "8#17", "1_000"; also "INT#-5" style
// typed literals and TRUE/FALSE (1/0).
std::optional<std::int64_t> parse_iec_integer(std::string_view s);
std::optional<std::uint64_t> parse_iec_unsigned(std::string_view s);
std::optional<double> parse_iec_real(std::string_view s);

// T#1s500ms; T#0s for zero; negative with a leading '-': T#-20ms.
std::string format_iec_time(TIME t);

// Parses `text` as a value of `type` into the storage at `dst` (which must be
// a live variable of that type). Returns an error message, or "" on success.
std::string parse_value(VarType type, std::string_view text, void* dst);
// Whether the raw value at `src` (native storage of `type`, as parse_value
// makes it) is one that parse_value could have made: a BOOL byte 0 or 1, a
// finite REAL/LREAL. "" if so, else why not. For values that come as bytes
// from another process (the HMI bridge): what the text path refuses, this
// refuses too. STRING is never a raw value ("not writable as bytes").
std::string check_raw_value(VarType type, const void* src);
// Prints the variable at `src` of `type` in IEC notation: TRUE, -5, 16#047F,
// 1.5, T#20ms, 'text'.
std::string format_value(VarType type, const void* src);
// format_value()'s text appended to `out`, with no string of its own (the
// trace's writer thread formats a row of values per scan).
void append_value(std::string& out, VarType type, const void* src);

}  // namespace plc

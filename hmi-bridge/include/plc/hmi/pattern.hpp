// The hmi: section's patterns (publish, writable, forceable) and plcctl's:
// a match over variable paths and addresses, `*` any run of characters
// (dots included), `?` any one character; `[` and `]` are literal, so
// `Cell.axes[0].*` matches the paths --list-vars prints for an array
// element; `\` escapes the next character.
#pragma once

#include <string>

namespace plc::hmi {

bool pattern_matches(const std::string& pattern, const std::string& text);

}  // namespace plc::hmi

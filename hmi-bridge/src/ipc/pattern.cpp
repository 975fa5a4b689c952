#include "plc/hmi/pattern.hpp"

#include <fnmatch.h>

namespace plc::hmi {

bool pattern_matches(const std::string& pattern, const std::string& text) {
  // Brackets are literal: they index arrays in the paths --list-vars prints
  // (`Cell.axes[0].pos`), and fnmatch would read `[0]` as a set of one
  // character. A backslash still escapes the next character (`\[0\]`, the
  // old way to write an index, keeps working).
  std::string glob;
  glob.reserve(pattern.size() + 4);
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    const char c = pattern[i];
    if (c == '\\' && i + 1 < pattern.size()) {
      glob += c;
      glob += pattern[++i];
    } else {
      if (c == '[' || c == ']') glob += '\\';
      glob += c;
    }
  }
  return fnmatch(glob.c_str(), text.c_str(), 0) == 0;
}

}  // namespace plc::hmi

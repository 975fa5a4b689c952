#include "plc/hmi/checked_decode.hpp"

#include <cstdint>
#include <cstdlib>

namespace plc::hmi {

namespace {

struct Reader {
  const std::uint8_t* p;
  std::size_t size;
  std::size_t at = 0;

  bool skip(std::size_t n) {
    if (n > size - at) return false;
    at += n;
    return true;
  }
  bool int32(std::int32_t& v) {
    if (4 > size - at) return false;
    v = std::int32_t(std::uint32_t(p[at]) << 24 | std::uint32_t(p[at + 1]) << 16 |
                     std::uint32_t(p[at + 2]) << 8 | std::uint32_t(p[at + 3]));
    at += 4;
    return true;
  }
};

// The end of the element that starts at s (one letter or a (..) group).
const char* element_end(const char* s) {
  if (*s != '(') return s + 1;
  int depth = 0;
  do {
    if (*s == '(') ++depth;
    if (*s == ')') --depth;
    ++s;
  } while (*s && depth > 0);
  return s;
}

bool sequence(Reader& r, const char* s, const char* end);

bool element(Reader& r, const char* s, std::int32_t& last_count) {
  switch (*s) {
    case 'b':
      return r.skip(1);
    case 'i':
      return r.skip(4);
    case 'l':
    case 'd':
      return r.skip(8);
    case 's': {  // int32 length with the NUL, then the bytes
      std::int32_t len = 0;
      return r.int32(len) && len >= 1 && r.skip(std::size_t(len));
    }
    case 'n': {  // every element takes at least one byte
      std::int32_t n = 0;
      if (!r.int32(n) || n < 0 || std::size_t(n) > r.size - r.at) return false;
      last_count = n;
      return true;
    }
    case '(':
      return sequence(r, s + 1, element_end(s) - 1);
    default:
      return false;  // a shape the walker does not know
  }
}

bool sequence(Reader& r, const char* s, const char* end) {
  std::int32_t last_count = 0;
  while (s < end) {
    std::int64_t repeat = 1;
    if (*s == '*') {
      repeat = last_count;
      ++s;
    } else if (*s >= '0' && *s <= '9') {
      char* after = nullptr;
      repeat = std::strtol(s, &after, 10);
      s = after;
    }
    const char* next = element_end(s);
    // Bounded: each element consumes at least one byte of the message.
    for (std::int64_t k = 0; k < repeat; ++k)
      if (!element(r, s, last_count)) return false;
    s = next;
  }
  return true;
}

}  // namespace

bool plausible_encoding(const char* shape, const void* data, std::size_t size) {
  Reader r{static_cast<const std::uint8_t*>(data), size};
  const char* end = shape;
  while (*end) ++end;
  return r.skip(8) && sequence(r, shape, end) && r.at == size;
}

}  // namespace plc::hmi

#include "plc/debug/recording_format.hpp"

#include <algorithm>
#include <new>

namespace plc::debug::recfmt {
namespace {

template <class U>
void put_native(Buf& b, const void* native) {
  U v;
  std::memcpy(&v, native, sizeof v);
  b.le(v);
}

template <class U>
bool get_native(In& in, void* native) {
  U v;
  if (!in.le(v)) return false;
  std::memcpy(native, &v, sizeof v);
  return true;
}

bool known_type(std::uint8_t t) { return t <= static_cast<std::uint8_t>(VarType::STRING); }

}  // namespace

void put_value(Buf& b, VarType type, const void* native) {
  if (type == VarType::STRING) {
    const auto& s = *static_cast<const STRING*>(native);
    b.u8(static_cast<std::uint8_t>(s.size()));
    b.bytes(s.c_str(), s.size());
    return;
  }
  if (type == VarType::BOOL) {
    b.u8(*static_cast<const bool*>(native) ? 1 : 0);
    return;
  }
  switch (size_of(type)) {
    case 1:
      put_native<std::uint8_t>(b, native);
      break;
    case 2:
      put_native<std::uint16_t>(b, native);
      break;
    case 4:
      put_native<std::uint32_t>(b, native);
      break;
    default:
      put_native<std::uint64_t>(b, native);
      break;
  }
}

bool get_value(In& in, VarType type, void* native) {
  if (type == VarType::STRING) {
    std::uint8_t n = 0;
    std::span<const std::uint8_t> chars;
    if (!in.le(n) || n > STRING::capacity || !in.take(n, chars)) return false;
    static_cast<STRING*>(native)->assign(
        std::string_view(reinterpret_cast<const char*>(chars.data()), n));
    return true;
  }
  if (type == VarType::BOOL) {
    std::uint8_t v = 0;
    if (!in.le(v) || v > 1) return false;  // any other byte is not a bool
    *static_cast<bool*>(native) = v != 0;
    return true;
  }
  switch (size_of(type)) {
    case 1:
      return get_native<std::uint8_t>(in, native);
    case 2:
      return get_native<std::uint16_t>(in, native);
    case 4:
      return get_native<std::uint32_t>(in, native);
    default:
      return get_native<std::uint64_t>(in, native);
  }
}

bool skip_value(In& in, std::uint8_t type) {
  if (!known_type(type)) return false;
  alignas(8) unsigned char buf[sizeof(STRING)];
  void* p = buf;
  if (static_cast<VarType>(type) == VarType::STRING) p = new (buf) STRING();
  return get_value(in, static_cast<VarType>(type), p);
}

std::uint64_t image_hash(std::span<const std::uint8_t> q, std::span<const std::uint8_t> m) {
  constexpr std::uint64_t kPrime = 0x100000001b3ULL;
  // Four independent lanes: the multiply chains overlap (about 4x faster on
  // a large %M than one chain).
  std::uint64_t lane[4];
  for (std::uint64_t i = 0; i < 4; ++i) lane[i] = 0xcbf29ce484222325ULL + i;
  std::size_t k = 0;
  for (auto area : {q, m}) {
    for (std::size_t i = 0; i < area.size(); i += 8, ++k) {
      std::uint64_t w = 0;
      std::memcpy(&w, area.data() + i, std::min<std::size_t>(8, area.size() - i));
      std::uint64_t& h = lane[k % 4];
      h = (h ^ boost::endian::little_to_native(w)) * kPrime;
      h ^= h >> 32;
    }
  }
  std::uint64_t h = lane[0];
  for (int i = 1; i < 4; ++i) {
    h = (h ^ lane[i]) * kPrime;
    h ^= h >> 32;
  }
  return h;
}

}  // namespace plc::debug::recfmt

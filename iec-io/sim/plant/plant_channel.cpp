#include "plant/plant_channel.hpp"

#include <cmath>
#include <limits>

namespace plc::plant {
namespace {

struct TypeInfo {
  const char* name;
  ChannelType type;
  std::size_t size;
  double lo, hi;  // raw range of the type
};

constexpr TypeInfo kTypes[] = {
    {"BOOL", ChannelType::BOOL, 1, 0, 1},
    {"SINT", ChannelType::SINT, 1, -128, 127},
    {"USINT", ChannelType::USINT, 1, 0, 255},
    {"INT", ChannelType::INT, 2, -32768, 32767},
    {"UINT", ChannelType::UINT, 2, 0, 65535},
    {"DINT", ChannelType::DINT, 4, -2147483648.0, 2147483647.0},
    {"UDINT", ChannelType::UDINT, 4, 0, 4294967295.0},
    {"REAL", ChannelType::REAL, 4, -std::numeric_limits<float>::max(),
     std::numeric_limits<float>::max()},
    {"LREAL", ChannelType::LREAL, 8, -std::numeric_limits<double>::max(),
     std::numeric_limits<double>::max()},
};

const TypeInfo& info(ChannelType t) {
  for (const auto& i : kTypes)
    if (i.type == t) return i;
  return kTypes[3];
}

bool is_real(ChannelType t) { return t == ChannelType::REAL || t == ChannelType::LREAL; }

// A [lo, hi] pair of finite numbers from `key`, lo != hi.
bool pair(const io::ModelParams& p, const std::string& key, double& a, double& b) {
  auto v = p.get_list(key);
  if (!v) return false;
  if (v->size() != 2)
    throw io::ParamError(key, "give two numbers, [low, high], not " + std::to_string(v->size()));
  a = (*v)[0];
  b = (*v)[1];
  if (a == b) throw io::ParamError(key, "the two ends must differ");
  return true;
}

}  // namespace

std::size_t type_size(ChannelType t) { return info(t).size; }

double ChannelCodec::decode(const std::uint8_t* p) const {
  double raw = 0;
  switch (type) {
    case ChannelType::BOOL:
      raw = (*p & 1) ? 1.0 : 0.0;
      break;
    case ChannelType::SINT:
      raw = io::load<std::int8_t>(p, order);
      break;
    case ChannelType::USINT:
      raw = io::load<std::uint8_t>(p, order);
      break;
    case ChannelType::INT:
      raw = io::load<std::int16_t>(p, order);
      break;
    case ChannelType::UINT:
      raw = io::load<std::uint16_t>(p, order);
      break;
    case ChannelType::DINT:
      raw = io::load<std::int32_t>(p, order);
      break;
    case ChannelType::UDINT:
      raw = io::load<std::uint32_t>(p, order);
      break;
    case ChannelType::REAL:
      raw = io::load<float>(p, order);
      break;
    case ChannelType::LREAL:
      raw = io::load<double>(p, order);
      break;
  }
  return saturation.apply(scale.to_eng(raw));
}

void ChannelCodec::encode(double eng, std::uint8_t* p) const {
  double raw = scale.to_raw(saturation.apply(eng));
  if (type == ChannelType::BOOL) {
    *p = static_cast<std::uint8_t>((*p & 0xFE) | (raw >= 0.5 ? 1 : 0));
    return;
  }
  const TypeInfo& ti = info(type);
  if (!is_real(type)) raw = std::round(raw);
  raw = std::min(std::max(raw, ti.lo), ti.hi);
  switch (type) {
    case ChannelType::BOOL:
      break;
    case ChannelType::SINT:
      io::store<std::int8_t>(p, static_cast<std::int8_t>(raw), order);
      break;
    case ChannelType::USINT:
      io::store<std::uint8_t>(p, static_cast<std::uint8_t>(raw), order);
      break;
    case ChannelType::INT:
      io::store<std::int16_t>(p, static_cast<std::int16_t>(raw), order);
      break;
    case ChannelType::UINT:
      io::store<std::uint16_t>(p, static_cast<std::uint16_t>(raw), order);
      break;
    case ChannelType::DINT:
      io::store<std::int32_t>(p, static_cast<std::int32_t>(raw), order);
      break;
    case ChannelType::UDINT:
      io::store<std::uint32_t>(p, static_cast<std::uint32_t>(raw), order);
      break;
    case ChannelType::REAL:
      io::store<float>(p, static_cast<float>(raw), order);
      break;
    case ChannelType::LREAL:
      io::store<double>(p, raw, order);
      break;
  }
}

ChannelCodec parse_codec(const io::ModelParams& p, const std::string& prefix, io::ByteOrder order) {
  ChannelCodec c;
  const std::string type = p.get_string(prefix + ".type", "INT");
  bool known = false;
  std::string names;
  for (const auto& i : kTypes) {
    names += (names.empty() ? "" : ", ") + std::string(i.name);
    if (type == i.name) {
      c.type = i.type;
      known = true;
    }
  }
  if (!known)
    throw io::ParamError(prefix + ".type", "unknown type '" + type + "' (one of " + names + ")");
  const std::string ord =
      p.get_string(prefix + ".order", order == io::ByteOrder::Big ? "big" : "little");
  if (ord != "big" && ord != "little")
    throw io::ParamError(prefix + ".order", "byte order is big or little, not '" + ord + "'");
  c.order = ord == "big" ? io::ByteOrder::Big : io::ByteOrder::Little;
  // Defaults: the S7 analog percent for integer types, 0/1 = 0/100 % for a
  // BOOL (a heater switched by a PWM output), the value itself for REALs.
  if (c.type == ChannelType::BOOL) {
    c.scale = {0, 1, 0, 100};
  } else if (!is_real(c.type)) {
    c.scale = {0, 27648, 0, 100};
  }
  const bool has_raw = pair(p, prefix + ".raw", c.scale.raw0, c.scale.raw1);
  const bool has_eng = pair(p, prefix + ".eng", c.scale.eng0, c.scale.eng1);
  if (c.type == ChannelType::BOOL && has_raw &&
      (std::min(c.scale.raw0, c.scale.raw1) != 0 || std::max(c.scale.raw0, c.scale.raw1) != 1))
    throw io::ParamError(prefix + ".raw", "a BOOL's raw values are 0 and 1");
  // An integer or BOOL channel is an analog module or a switch: saturated
  // to its engineering range unless min/max say otherwise. A REAL is not
  // saturated unless asked.
  if (!is_real(c.type) || has_raw || has_eng) {
    c.saturation.lo = std::min(c.scale.eng0, c.scale.eng1);
    c.saturation.hi = std::max(c.scale.eng0, c.scale.eng1);
  }
  constexpr double kBig = 1e300;
  c.saturation.lo = p.get_double(prefix + ".min", c.saturation.lo, -kBig, kBig);
  c.saturation.hi = p.get_double(prefix + ".max", c.saturation.hi, -kBig, kBig);
  if (c.saturation.lo > c.saturation.hi)
    throw io::ParamError(prefix + ".max", prefix + ".max is below " + prefix + ".min");
  return c;
}

}  // namespace plc::plant

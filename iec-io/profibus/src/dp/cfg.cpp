#include "plc/profibus/dp/cfg.hpp"

#include <cstdio>

namespace plc::profibus::dp {

std::optional<CfgSizes> cfg_sizes(std::span<const std::uint8_t> cfg) {
  CfgSizes s;
  std::size_t i = 0;
  auto len = [](std::uint8_t b, std::size_t count) { return (b & 0x40) ? 2 * count : count; };
  while (i < cfg.size()) {
    const std::uint8_t id = cfg[i++];
    ++s.identifiers;
    if (id & 0x30) {
      const std::size_t n = len(id, (id & 0x0F) + 1u);
      if (id & 0x10) s.input_bytes += n;
      if (id & 0x20) s.output_bytes += n;
      continue;
    }
    const std::size_t manufacturer = id & 0x0F;
    const std::uint8_t kind = id >> 6;
    if (kind & 0x2) {  // an output length byte
      if (i >= cfg.size()) return std::nullopt;
      const std::uint8_t b = cfg[i++];
      s.output_bytes += len(b, (b & 0x3F) + 1u);
    }
    if (kind & 0x1) {  // an input length byte
      if (i >= cfg.size()) return std::nullopt;
      const std::uint8_t b = cfg[i++];
      s.input_bytes += len(b, (b & 0x3F) + 1u);
    }
    if (i + manufacturer > cfg.size()) return std::nullopt;
    i += manufacturer;
  }
  return s;
}

std::string hex(std::span<const std::uint8_t> bytes) {
  std::string s;
  char b[4];
  for (const std::uint8_t x : bytes) {
    std::snprintf(b, sizeof b, "%02X", x);
    if (!s.empty()) s += ' ';
    s += b;
  }
  return s;
}

}  // namespace plc::profibus::dp

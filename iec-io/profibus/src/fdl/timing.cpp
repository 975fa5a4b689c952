#include "plc/profibus/fdl/timing.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

namespace plc::profibus::fdl {

namespace {
// The DP bus profile's defaults per baud rate (TSL, minTSDR, maxTSDR in bit
// times; TQUI, TSET; max_retry_limit).
constexpr std::array<BaudProfile, 10> kProfiles{{
    {9600, "9.6", 100, 11, 60, 0, 1, 1},
    {19200, "19.2", 100, 11, 60, 0, 1, 1},
    {45450, "45.45", 640, 11, 400, 0, 95, 1},
    {93750, "93.75", 100, 11, 60, 0, 1, 1},
    {187500, "187.5", 100, 11, 60, 0, 1, 1},
    {500000, "500", 200, 11, 100, 0, 1, 1},
    {1500000, "1.5M", 300, 11, 150, 0, 1, 1},
    {3000000, "3M", 400, 11, 250, 3, 4, 2},
    {6000000, "6M", 600, 11, 450, 6, 8, 3},
    {12000000, "12M", 1000, 11, 800, 9, 16, 4},
}};
}  // namespace

const BaudProfile* baud_profile(std::uint32_t baud) {
  for (const auto& p : kProfiles)
    if (p.baud == baud) return &p;
  return nullptr;
}

std::span<const BaudProfile> baud_profiles() { return kProfiles; }

std::size_t telegram_chars(std::size_t unit) {
  if (unit == 0) return 6;
  if (unit == 8) return 14;
  return 9 + unit;
}

std::uint64_t message_cycle_bits(const BusParameters& p, std::size_t req_unit, std::size_t res_unit,
                                 std::uint32_t tsdr) {
  const std::size_t res_chars = res_unit == SIZE_MAX ? 1 : telegram_chars(res_unit);
  return kBitsPerChar * telegram_chars(req_unit) + tsdr + kBitsPerChar * res_chars + p.tid1;
}

std::uint64_t bus_cycle_bits(const BusParameters& p, std::size_t slaves, std::size_t out_bytes,
                             std::size_t in_bytes, std::uint32_t tsdr) {
  // The token telegram (3 characters) to itself, then TID2 (no answer).
  std::uint64_t bits = kBitsPerChar * 3 + p.tid2;
  for (std::size_t i = 0; i < slaves; ++i)
    bits += message_cycle_bits(p, out_bytes, in_bytes == 0 ? SIZE_MAX : in_bytes, tsdr);
  return bits;
}

std::uint32_t ttr_for(const BusParameters& p, std::size_t slaves, std::size_t io_bytes) {
  std::uint64_t bits = bus_cycle_bits(p, slaves, io_bytes, io_bytes, p.max_tsdr);
  bits += kBitsPerChar * telegram_chars(io_bytes) + p.tsl;  // one retry
  bits += kBitsPerChar * telegram_chars(0) + p.tsl;         // one GAP request
  bits = (bits + 255) / 256 * 256;
  return static_cast<std::uint32_t>(std::min<std::uint64_t>(bits, 0xFFFFFF));
}

BusParameters bus_parameters(std::uint32_t baud, std::span<const std::uint32_t> slave_max_tsdr,
                             std::size_t slaves, std::size_t io_bytes) {
  const BaudProfile* prof = baud_profile(baud);
  BusParameters p;
  if (!prof) return p;
  p.baud = baud;
  p.tsl = prof->tsl;
  p.min_tsdr = prof->min_tsdr;
  p.max_tsdr = prof->max_tsdr;
  p.tqui = prof->tqui;
  p.tset = prof->tset;
  p.max_retry = prof->max_retry;
  for (const std::uint32_t t : slave_max_tsdr) p.max_tsdr = std::max(p.max_tsdr, t);
  // The slot time covers the longest answer delay, the quiet and set-up
  // times and the first character of the answer.
  p.tsl = std::max(p.tsl, p.max_tsdr + p.tqui + p.tset + kBitsPerChar);
  p.tid1 = std::max(kTsyn + p.tset, p.min_tsdr);
  p.tid2 = std::max(kTsyn + p.tset, p.max_tsdr);
  p.ttr = ttr_for(p, slaves, io_bytes);
  return p;
}

std::string BusParameters::describe() const {
  char b[256];
  std::snprintf(b, sizeof b,
                "%u bit/s: TSL %u, minTSDR %u, maxTSDR %u, TSYN %u, TQUI %u, TSET %u, TID1 %u, "
                "TID2 %u, TTR %u bit times; max_retry %u, G %u, HSA %u",
                baud, tsl, min_tsdr, max_tsdr, kTsyn, tqui, tset, tid1, tid2, ttr, max_retry,
                gap_factor, hsa);
  return b;
}

}  // namespace plc::profibus::fdl

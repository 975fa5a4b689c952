// PROFIBUS bus timing (EN 50170 vol. 2 / IEC 61158-4-3), in bit times
// (t_bit = 1 / baud rate):
//   TSYN   33     idle time before every request (synchronisation)
//   TSL           slot time: how long the initiator waits for the first
//                 character of an answer; past it the request is repeated
//                 (up to max_retry times), then the station counts as lost
//   minTSDR/maxTSDR  the shortest/longest delay of a responder's answer
//                 (maxTSDR per baud rate from each slave's GSD)
//   TQUI          quiet time of a transmitter (repeater switch-over)
//   TSET          set-up time (reaction to an event)
//   TID1 = max(TSYN + TSET, minTSDR)  idle time after an answer
//   TID2 = max(TSYN + TSET, maxTSDR)  idle time after an unanswered (SDN) request
//   TTR           target rotation time of the token
// The defaults per baud rate are the DP bus profile's (the values DP
// configuration tools enter by default); a slave's GSD can only make
// maxTSDR (and with it TSL) longer.
//
// Every character is 11 bits (start, 8 data, even parity, stop), sent
// without gaps: a telegram of n characters takes 11 n bit times.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "plc/types.hpp"

namespace plc::profibus::fdl {

inline constexpr std::uint32_t kTsyn = 33;
inline constexpr std::uint32_t kBitsPerChar = 11;

struct BaudProfile {
  std::uint32_t baud;
  const char* gsd_suffix;  // MaxTsdr_<suffix>, <suffix>_supp in a GSD
  std::uint16_t tsl, min_tsdr, max_tsdr;
  std::uint8_t tqui, tset, max_retry;
};

// The ten baud rates, 9.6 kbit/s to 12 Mbit/s; nullptr for another rate.
const BaudProfile* baud_profile(std::uint32_t baud);
std::span<const BaudProfile> baud_profiles();

struct BusParameters {
  std::uint32_t baud = 1500000;
  std::uint32_t tsl = 300, min_tsdr = 11, max_tsdr = 150, tqui = 0, tset = 1;
  std::uint32_t tid1 = 0, tid2 = 0, ttr = 0;
  std::uint8_t max_retry = 1;
  std::uint8_t gap_factor = 10;  // GAP update every G token rotations
  std::uint8_t hsa = 126;        // highest station address

  [[nodiscard]] TIME bits(std::uint64_t n) const {
    return TIME(static_cast<std::int64_t>(n * 1'000'000'000ULL / baud));
  }
  [[nodiscard]] std::string describe() const;
};

// The parameters for `baud` (which must have a profile): the profile's
// values, maxTSDR raised to the longest of `slave_max_tsdr` (the GSDs'
// MaxTsdr at this rate), TSL raised so that it covers maxTSDR and the first
// character of the answer, TID1/TID2 from TSYN, TSET and the TSDRs, and
// TTR for `slaves` message cycles of `io_bytes` each way (see
// ttr_for()).
BusParameters bus_parameters(std::uint32_t baud, std::span<const std::uint32_t> slave_max_tsdr,
                             std::size_t slaves, std::size_t io_bytes);

// Characters of a telegram with a data unit of `unit` bytes (SAP bytes
// included): SD1 6, SD3 14, SD2 9 + unit.
std::size_t telegram_chars(std::size_t unit);

// One message cycle, in bit times: TSYN... the request of `req_unit` data
// bytes, the answer after `tsdr`, the answer of `res_unit` bytes (SIZE_MAX:
// a short acknowledgement), then TID1 before the next request (TID1 covers
// TSYN).
std::uint64_t message_cycle_bits(const BusParameters& p, std::size_t req_unit, std::size_t res_unit,
                                 std::uint32_t tsdr);

// The bus cycle of a single master with `slaves` slaves exchanging
// `out_bytes`/`in_bytes` each (Data_Exchange, no SAPs), plus the token it
// passes to itself; with the slaves answering after `tsdr` bit times.
std::uint64_t bus_cycle_bits(const BusParameters& p, std::size_t slaves, std::size_t out_bytes,
                             std::size_t in_bytes, std::uint32_t tsdr);

// TTR: the worst-case bus cycle (every slave answering at maxTSDR), one
// retry (TSL plus a repeated request) and one GAP request (FDL status plus
// TSL), rounded up to 256 bit times.
std::uint32_t ttr_for(const BusParameters& p, std::size_t slaves, std::size_t io_bytes);

}  // namespace plc::profibus::fdl

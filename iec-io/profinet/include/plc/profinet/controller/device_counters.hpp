// Per-device counters of the PROFINET IO controller (diagnostics(), stats).
#pragma once

#include <cstdint>

namespace plc::profinet {

// Why a frame addressed to a device's AR was dropped. Every dropped frame
// is counted under exactly one reason.
enum class BadFrame : std::uint8_t {
  Decode,          // the codec refused it (truncated, wrong lengths, bad header)
  SourceMac,       // a cyclic/alarm frame for our FrameID from another MAC
  Length,          // cyclic frame whose C_SDU length is not the IOCR's
  TransferStatus,  // TransferStatus not 0
  DataInvalid,     // DataStatus without DataValid
  StaleCounter,    // cycle counter repeated or went backwards (61440 rule)
  UnknownFrameId,  // no AR of ours uses this FrameID
  Rpc,             // an RPC answer that fits no request of ours, or is malformed
  kCount
};
const char* to_string(BadFrame b);

struct DeviceCounters {
  std::uint64_t frames_out = 0;  // cyclic output frames sent
  std::uint64_t frames_in = 0;   // valid cyclic input frames taken
  std::uint64_t late = 0;        // output frames sent a whole interval or more after due
  std::uint64_t lost = 0;        // input frames missing (gaps in the device's cycle counter)
  std::uint64_t bad[static_cast<int>(BadFrame::kCount)] = {};
  std::uint64_t connects = 0;        // ARs established (ApplicationReady answered)
  std::uint64_t connect_errors = 0;  // Connect/Write/PrmEnd refused or timed out
  std::uint64_t losses = 0;          // data-hold timeouts (or AR aborted) while connected
  std::uint64_t alarms = 0;          // alarm notifications received (and acknowledged)
  std::uint64_t records_ok = 0, records_error = 0, records_timeout = 0;
  [[nodiscard]] std::uint64_t bad_total() const {
    std::uint64_t n = 0;
    for (auto b : bad) n += b;
    return n;
  }
};

}  // namespace plc::profinet

// Writes CAN frames to a pcap file with link type 227
// (LINKTYPE_CAN_SOCKETCAN) so Wireshark/tshark can decode the capture:
//   tshark -r bus.pcap -d 'can.subdissector,devicenet'   (Wireshark 4.0)
// Each record is the 16-byte SocketCAN can_frame with the identifier
// (flags included) big-endian, as that link type requires. The file itself
// is plc::io::PcapFile (shared with the PROFINET Ethernet captures).
#pragma once

#include <cstdint>
#include <string>

#include "plc/can/frame.hpp"
#include "plc/io/pcap_file.hpp"

namespace plc::can {

inline constexpr std::uint32_t kLinkTypeCanSocketcan = io::kLinkTypeCanSocketcan;

class PcapWriter {
 public:
  // Creates (truncates) the file; throws BusError when it cannot.
  explicit PcapWriter(const std::string& path);
  PcapWriter(const PcapWriter&) = delete;
  PcapWriter& operator=(const PcapWriter&) = delete;
  // ts_ns: the frame's time stamp (any epoch).
  void write(const Frame& f, std::int64_t ts_ns);
  void flush();

 private:
  io::PcapFile file_;
};

}  // namespace plc::can

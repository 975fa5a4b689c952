// A pcap capture file (the classic libpcap format, microsecond time stamps,
// little-endian) of any link type, so captures of our buses go to
// Wireshark/tshark: LINKTYPE_ETHERNET for PROFINET (raw frames and the
// UDP/IPv4 RPC datagrams), LINKTYPE_CAN_SOCKETCAN for CAN (plc::can::PcapWriter).
#pragma once

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>

namespace plc::io {

inline constexpr std::uint32_t kLinkTypeEthernet = 1;
inline constexpr std::uint32_t kLinkTypeCanSocketcan = 227;

class PcapFile {
 public:
  // Creates (truncates) the file and writes the global header; throws
  // std::runtime_error with the reason when it cannot.
  PcapFile(const std::string& path, std::uint32_t link_type, std::uint32_t snaplen = 65535);
  ~PcapFile();
  PcapFile(const PcapFile&) = delete;
  PcapFile& operator=(const PcapFile&) = delete;
  // One record; ts_ns: its time stamp (any epoch). Records longer than the
  // snaplen are cut to it (orig_len keeps the full length).
  void write(std::span<const std::uint8_t> record, std::int64_t ts_ns);
  void flush();

 private:
  std::FILE* file_ = nullptr;
  std::uint32_t snaplen_;
};

}  // namespace plc::io

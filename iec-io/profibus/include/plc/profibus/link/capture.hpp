// A capture of every telegram a station sends and receives:
//  - text: one line per telegram, decoded down to the DP service
//      "     12.345678 tx SD2 2->8 SRD_high FCB=1 DSAP 61 SSAP 62 Set_Prm: ... | 68 0C 0C 68 ..."
//  - pcap with LINKTYPE_PROFIBUS_DL (257: "PROFIBUS data link layer packets,
//    as specified by IEC 61158-4-3, beginning with the start delimiter").
//    Wireshark 4.0 does not open that link type ("network type 257 unknown
//    or unsupported"; it has no PROFIBUS FDL dissector): the text file is
//    the decoded view, the pcap keeps the raw telegrams with time stamps.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <span>
#include <string>

#include "plc/io/pcap_file.hpp"
#include "plc/profibus/fdl/telegram.hpp"

namespace plc::profibus::link {

inline constexpr std::uint32_t kLinkTypeProfibusDl = 257;

class Capture {
 public:
  // Either path may be empty. Throws std::runtime_error when a file cannot
  // be created.
  Capture(const std::string& text_path, const std::string& pcap_path);
  ~Capture();
  Capture(const Capture&) = delete;
  Capture& operator=(const Capture&) = delete;
  // `tx`: sent by this station; `t`: the decoded telegram of `raw`.
  void record(std::int64_t ts_ns, bool tx, std::span<const std::uint8_t> raw,
              const fdl::Telegram& t);
  // Bytes that started no telegram (dropped by the deframer).
  void note(std::int64_t ts_ns, const std::string& text);
  void flush();
  [[nodiscard]] std::uint64_t telegrams() const { return count_; }

 private:
  std::FILE* text_ = nullptr;
  std::unique_ptr<io::PcapFile> pcap_;
  std::uint64_t count_ = 0;
};

}  // namespace plc::profibus::link

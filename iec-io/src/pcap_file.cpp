#include "plc/io/pcap_file.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace plc::io {

namespace {
// pcap fields are in the writer's byte order (the magic tells the reader
// which); we write little-endian explicitly so the file is the same on
// every host.
void le32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
void le16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}
}  // namespace

PcapFile::PcapFile(const std::string& path, std::uint32_t link_type, std::uint32_t snaplen)
    : snaplen_(snaplen) {
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_)
    throw std::runtime_error("pcap: cannot create '" + path + "': " + std::strerror(errno));
  std::array<std::uint8_t, 24> h{};
  le32(&h[0], 0xA1B2C3D4u);  // microsecond time stamps
  le16(&h[4], 2);
  le16(&h[6], 4);
  le32(&h[16], snaplen);
  le32(&h[20], link_type);
  std::fwrite(h.data(), 1, h.size(), file_);
}

PcapFile::~PcapFile() {
  if (file_) std::fclose(file_);
}

void PcapFile::write(std::span<const std::uint8_t> record, std::int64_t ts_ns) {
  const auto incl = static_cast<std::uint32_t>(std::min<std::size_t>(record.size(), snaplen_));
  std::array<std::uint8_t, 16> r{};
  le32(&r[0], static_cast<std::uint32_t>(ts_ns / 1'000'000'000));
  le32(&r[4], static_cast<std::uint32_t>((ts_ns % 1'000'000'000) / 1000));
  le32(&r[8], incl);
  le32(&r[12], static_cast<std::uint32_t>(record.size()));
  std::fwrite(r.data(), 1, r.size(), file_);
  std::fwrite(record.data(), 1, incl, file_);
}

void PcapFile::flush() { std::fflush(file_); }

}  // namespace plc::io

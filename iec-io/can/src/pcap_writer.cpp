#include "plc/can/pcap_writer.hpp"

#include <array>
#include <cerrno>
#include <cstring>

#include "plc/can/bus.hpp"

namespace plc::can {

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

PcapWriter::PcapWriter(const std::string& path) {
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) throw BusError("pcap: cannot create '" + path + "': " + std::strerror(errno));
  std::array<std::uint8_t, 24> h{};
  le32(&h[0], 0xA1B2C3D4u);  // microsecond time stamps
  le16(&h[4], 2);
  le16(&h[6], 4);
  le32(&h[16], 65535);  // snaplen
  le32(&h[20], kLinkTypeCanSocketcan);
  std::fwrite(h.data(), 1, h.size(), file_);
}

PcapWriter::~PcapWriter() {
  if (file_) std::fclose(file_);
}

void PcapWriter::write(const Frame& f, std::int64_t ts_ns) {
  std::array<std::uint8_t, 16 + 16> r{};
  le32(&r[0], static_cast<std::uint32_t>(ts_ns / 1'000'000'000));
  le32(&r[4], static_cast<std::uint32_t>((ts_ns % 1'000'000'000) / 1000));
  le32(&r[8], 16);
  le32(&r[12], 16);
  std::uint8_t* c = &r[16];
  c[0] = static_cast<std::uint8_t>(f.id >> 24);  // can_id, big-endian (link type 227)
  c[1] = static_cast<std::uint8_t>(f.id >> 16);
  c[2] = static_cast<std::uint8_t>(f.id >> 8);
  c[3] = static_cast<std::uint8_t>(f.id);
  c[4] = f.len;  // can_dlc; bytes 5..7 padding/reserved
  std::memcpy(c + 8, f.data.data(), 8);
  std::fwrite(r.data(), 1, r.size(), file_);
}

void PcapWriter::flush() { std::fflush(file_); }

}  // namespace plc::can

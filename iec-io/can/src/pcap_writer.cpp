#include "plc/can/pcap_writer.hpp"

#include <array>
#include <cstring>
#include <stdexcept>

#include "plc/can/bus.hpp"

namespace plc::can {

PcapWriter::PcapWriter(const std::string& path) try : file_(path, kLinkTypeCanSocketcan) {
} catch (const std::runtime_error& e) {
  throw BusError(e.what());
}

void PcapWriter::write(const Frame& f, std::int64_t ts_ns) {
  std::array<std::uint8_t, 16> c{};
  c[0] = static_cast<std::uint8_t>(f.id >> 24);  // can_id, big-endian (link type 227)
  c[1] = static_cast<std::uint8_t>(f.id >> 16);
  c[2] = static_cast<std::uint8_t>(f.id >> 8);
  c[3] = static_cast<std::uint8_t>(f.id);
  c[4] = f.len;  // can_dlc; bytes 5..7 padding/reserved
  std::memcpy(c.data() + 8, f.data.data(), 8);
  file_.write(c, ts_ns);
}

void PcapWriter::flush() { file_.flush(); }

}  // namespace plc::can

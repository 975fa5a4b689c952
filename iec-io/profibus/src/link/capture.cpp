#include "plc/profibus/link/capture.hpp"

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "plc/profibus/dp/cfg.hpp"
#include "plc/profibus/dp/describe.hpp"

namespace plc::profibus::link {

Capture::Capture(const std::string& text_path, const std::string& pcap_path) {
  if (!text_path.empty()) {
    text_ = std::fopen(text_path.c_str(), "w");
    if (!text_) throw std::runtime_error(text_path + ": " + std::strerror(errno));
  }
  if (!pcap_path.empty()) pcap_ = std::make_unique<io::PcapFile>(pcap_path, kLinkTypeProfibusDl);
}

Capture::~Capture() {
  if (text_) std::fclose(text_);
}

void Capture::record(std::int64_t ts_ns, bool tx, std::span<const std::uint8_t> raw,
                     const fdl::Telegram& t) {
  ++count_;
  if (pcap_) pcap_->write(raw, ts_ns);
  if (text_)
    std::fprintf(text_, "%14.6f %s %s | %s\n", static_cast<double>(ts_ns) / 1e6, tx ? "tx" : "rx",
                 dp::describe(t).c_str(), dp::hex(raw).c_str());
}

void Capture::note(std::int64_t ts_ns, const std::string& text) {
  if (text_) std::fprintf(text_, "%14.6f -- %s\n", static_cast<double>(ts_ns) / 1e6, text.c_str());
}

void Capture::flush() {
  if (text_) std::fflush(text_);
  if (pcap_) pcap_->flush();
}

}  // namespace plc::profibus::link

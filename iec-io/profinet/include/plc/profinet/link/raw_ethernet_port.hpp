// A Linux network interface as an EthernetPort: an AF_PACKET SOCK_RAW socket
// bound to the interface for EtherType 0x8892.
//
// VLAN: the kernel takes the 802.1Q tag off a received frame and passes it
// beside the frame (PACKET_AUXDATA, tp_vlan_tci); receive() puts it back, so
// a tagged frame is seen as it was on the wire (devices may send priority-6
// tagged frames, fieldbus-masters.md §1 item 6). A frame given to send()
// with a tag goes out tagged.
// Membership: the DCP multicasts 01:0E:CF:00:00:00 (Identify) and :01
// (Hello) always; the whole
// interface in promiscuous mode when asked (both end with the socket).
// Needs CAP_NET_RAW: without it, or without the interface, the constructor
// throws LinkError saying so.
#pragma once

#include <string>

#include "plc/profinet/link/ethernet_port.hpp"

namespace plc::profinet {

struct RawEthernetOptions {
  bool promiscuous = false;
};

class RawEthernetPort final : public EthernetPort {
 public:
  explicit RawEthernetPort(const std::string& interface, RawEthernetOptions options = {});
  ~RawEthernetPort() override;
  RawEthernetPort(const RawEthernetPort&) = delete;
  RawEthernetPort& operator=(const RawEthernetPort&) = delete;

  [[nodiscard]] Mac mac() const override { return mac_; }
  bool send(std::span<const std::uint8_t> frame) override;
  std::size_t receive(std::span<std::uint8_t> buf, std::chrono::nanoseconds timeout) override;
  [[nodiscard]] int fd() const override { return fd_; }
  [[nodiscard]] const std::string& interface() const { return interface_; }
  [[nodiscard]] int ifindex() const { return ifindex_; }

 private:
  std::string interface_;
  int ifindex_ = 0;
  int fd_ = -1;
  Mac mac_{};
};

}  // namespace plc::profinet

// CAN over UDP. One UDP "bus" is a hub (UdpHub, a thread in any process,
// e.g. the scanner's) that forwards every datagram it receives to every node
// it has heard from, the sender included, so every node sees every frame as
// on a wire, its own transmissions too (like SocketCAN's own-message echo).
// A node makes itself known with a keep-alive datagram (frame count 0) when
// it opens and once a second; the hub forgets a node not heard for 5 s.
//
// Why a hub and not multicast: multicast on loopback needs the MULTICAST
// flag on `lo` (a host change) or a network namespace (root); a hub needs
// nothing and works across machines as well. The datagram format is
// cannelloni's (udp_datagram.hpp), so a cannelloni gateway can be a node.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "plc/can/bus.hpp"
#include "plc/can/udp_datagram.hpp"

namespace plc::can {

class UdpBus final : public Bus {
 public:
  // host: an IPv4 address or name; throws BusError.
  UdpBus(const std::string& host, std::uint16_t port);
  ~UdpBus() override;
  bool send(const Frame& f) override;
  bool receive(Frame& f) override;
  int fd() const override { return fd_; }
  const BusCounters& counters() const override { return counters_; }

 private:
  void keep_alive(bool force);
  int fd_ = -1;
  std::uint8_t seq_ = 0;
  std::int64_t last_tx_ns_ = 0;
  std::array<Frame, udp::kMaxFramesPerDatagram> pending_{};
  std::size_t pending_n_ = 0, pending_pos_ = 0;
  BusCounters counters_;
};

class UdpHub {
 public:
  // Binds host:port (port 0: any free port, see port()); throws BusError.
  UdpHub(const std::string& host, std::uint16_t port);
  ~UdpHub();
  UdpHub(const UdpHub&) = delete;
  UdpHub& operator=(const UdpHub&) = delete;
  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] std::uint64_t forwarded() const { return forwarded_.load(); }
  [[nodiscard]] std::uint64_t rejected() const { return rejected_.load(); }

 private:
  void run();
  int fd_ = -1;
  int wake_[2] = {-1, -1};
  std::uint16_t port_ = 0;
  std::thread thread_;
  std::atomic<std::uint64_t> forwarded_{0}, rejected_{0};
};

}  // namespace plc::can

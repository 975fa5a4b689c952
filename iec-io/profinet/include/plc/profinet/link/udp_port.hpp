// UDP datagrams of the PROFINET acyclic side (DCE/RPC on port 34964).
// Implementations: SocketUdpPort (a POSIX socket) and MemoryUdp ports.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>

#include "plc/profinet/link/address.hpp"
#include "plc/profinet/link/ethernet_port.hpp"

namespace plc::profinet {

inline constexpr std::uint16_t kPnioRpcPort = 34964;  // 0x8894
// Largest datagram a port sends or delivers (IPv4, no fragmentation on an
// Ethernet link: 1500 - 20 - 8).
inline constexpr std::size_t kMaxDatagram = 1472;

class UdpPort {
 public:
  virtual ~UdpPort() = default;
  [[nodiscard]] virtual Ipv4 local_ip() const = 0;
  [[nodiscard]] virtual std::uint16_t local_port() const = 0;
  // false: not sent (counted in send_failed).
  virtual bool send_to(Ipv4 ip, std::uint16_t port, std::span<const std::uint8_t> data) = 0;
  // Waits at most `timeout` (0 = just look). Returns the datagram's length
  // (and its source), 0 if none came. A datagram longer than `buf` is
  // dropped (rx_dropped).
  virtual std::size_t receive_from(std::span<std::uint8_t> buf, Ipv4& ip, std::uint16_t& port,
                                   std::chrono::nanoseconds timeout) = 0;
  [[nodiscard]] virtual int fd() const { return -1; }
  // Where an in-memory port counts the messages queued for it, or null: a
  // poll that reads 0 there may skip receive with timeout 0, which looks at
  // the same count first and would return nothing.
  [[nodiscard]] virtual const std::atomic<std::size_t>* queued_count() const { return nullptr; }
  [[nodiscard]] const LinkCounters& counters() const { return counters_; }

 protected:
  LinkCounters counters_;
};

}  // namespace plc::profinet

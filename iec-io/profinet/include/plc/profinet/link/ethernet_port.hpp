// Raw Ethernet frames of the PROFINET RT and DCP traffic (EtherType 0x8892).
// Implementations: RawEthernetPort (AF_PACKET on a Linux interface) and
// MemoryEthernet ports (in-memory hub for lockstep tests).
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>

#include "plc/profinet/link/address.hpp"
#include "plc/profinet/wire/ethernet.hpp"  // kEtherTypeProfinet, kMaxFrameLength

namespace plc::profinet {

// Counters of one port; atomics so a diagnostics thread may read them while
// the real-time thread sends and receives.
struct LinkCounters {
  std::atomic<std::uint64_t> sent{0};
  std::atomic<std::uint64_t> send_failed{0};  // send() returned false (link down, error, drop)
  std::atomic<std::uint64_t> received{0};     // frames delivered by receive()
  std::atomic<std::uint64_t> rx_dropped{0};   // not delivered: too long for the buffer, malformed
};

class EthernetPort {
 public:
  virtual ~EthernetPort() = default;
  [[nodiscard]] virtual Mac mac() const = 0;
  // Sends one whole frame: destination, source, [VLAN tag 0x8100 + TCI,]
  // EtherType, payload (no FCS). A frame that carries a VLAN tag goes out
  // tagged. false: not sent (counted in send_failed).
  virtual bool send(std::span<const std::uint8_t> frame) = 0;
  // Waits at most `timeout` (0 = just look) for the next EtherType 0x8892
  // frame, tagged or untagged, and copies it, byte for byte as on the wire
  // (a tag the kernel took off is put back), into `buf`. Returns its length,
  // 0 if none came. A frame longer than `buf` is dropped (rx_dropped).
  virtual std::size_t receive(std::span<std::uint8_t> buf, std::chrono::nanoseconds timeout) = 0;
  // receive() without the copy where the port can avoid it: the frame
  // where it lies (a MemoryEthernet port: the hub's buffer), valid until
  // this port's next receive() or receive_view(). Other ports copy it into
  // `buf` and return that part of `buf`. Empty if none came; a frame longer
  // than `buf` is dropped, as by receive().
  virtual std::span<const std::uint8_t> receive_view(std::span<std::uint8_t> buf,
                                                     std::chrono::nanoseconds timeout) {
    return buf.first(receive(buf, timeout));
  }
  // A descriptor that becomes readable when a frame may be there (poll()),
  // or -1 (in-memory ports).
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

// An in-memory Ethernet hub for lockstep tests in virtual time: every frame
// a port sends is, at once, in the receive queue of every other port whose
// link is up (a hub, not a switch: destination-MAC filtering is the
// receiver's job, as on a real shared segment). No threads and no sleeping;
// a mutex makes it safe to use from several threads too (receive() with a
// timeout then waits on a condition variable).
//
// set_single_threaded(true) declares that one thread alone uses the hub
// from now on (every port, every call here), as in a cell in virtual time,
// whose scan thread steps the controller and the simulated devices: the hub
// then takes no lock, and receive() does not wait (no other thread could
// send the frame it waits for). Its owner declares it, and takes it back
// (false) before another thread may use the hub again; both while no other
// thread uses it.
//
// Fault hooks act on the frames a given port sends: drop the next n, delay
// the next n by d of the hub's time (set_time(); a delayed frame is
// delivered once the hub's time reaches its send time + d, in send order),
// link down (the port sends nothing, counted in send_failed, and receives
// nothing; frames queued for it are lost).
//
// A port opened with `promiscuous` false sees, as an interface's raw socket
// without promiscuous mode, only the frames to its own MAC and to group
// addresses (multicast, broadcast): the profinet plugin's controller and
// simulated devices take nothing else, and a frame of theirs then costs
// no copy and no look at the other ports. Ports are promiscuous by default
// (a tap sees everything).
//
// MemoryEthernet is a handle: copies share one hub, and a port keeps its hub
// alive.
#pragma once

#include <chrono>
#include <memory>

#include "plc/profinet/link/ethernet_port.hpp"

namespace plc::profinet {

class MemoryEthernet {
 public:
  MemoryEthernet();

  // A new port. A zero MAC takes the next locally administered one
  // (02:00:00:00:00:01, :02, ...). Throws LinkError if the MAC is taken.
  std::unique_ptr<EthernetPort> port(Mac mac = {}, bool promiscuous = true);

  void drop_next(const Mac& from, int n);
  void delay_next(const Mac& from, int n, std::chrono::nanoseconds d);
  void set_link_up(const Mac& port, bool up);
  void set_single_threaded(bool yes);
  [[nodiscard]] bool single_threaded() const;
  void set_time(std::chrono::nanoseconds now);
  [[nodiscard]] std::chrono::nanoseconds time() const;
  [[nodiscard]] std::uint64_t frames_carried() const;  // frames sent through the hub

  struct Impl;

 private:
  std::shared_ptr<Impl> impl_;
};

// Frames one port's queue holds at most; more are dropped (rx_dropped).
inline constexpr std::size_t kMemoryQueueLimit = 4096;

}  // namespace plc::profinet

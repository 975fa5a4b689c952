#include "plc/can/socketcan_bus.hpp"

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace plc::can {

BusState bus_state_after(BusState before, const Frame& err) {
  if (!err.error()) return before;
  if (err.id & CAN_ERR_BUSOFF) return BusState::BusOff;
  if (err.id & CAN_ERR_RESTARTED) return BusState::ErrorActive;
  if ((err.id & CAN_ERR_CRTL) && err.len > 1) {
    const std::uint8_t c = err.data[1];
    if (c & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) return BusState::ErrorPassive;
#ifdef CAN_ERR_CRTL_ACTIVE
    if (c & CAN_ERR_CRTL_ACTIVE) return BusState::ErrorActive;
#endif
  }
  return before;
}

SocketCanBus::SocketCanBus(const std::string& ifname) {
  if (ifname.empty() || ifname.size() >= IFNAMSIZ)
    throw BusError("socketcan: bad interface name '" + ifname + "'");
  fd_ = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0)
    throw BusError("socketcan " + ifname + ": socket(PF_CAN): " + std::strerror(errno) +
                   " (no CAN support in this kernel?)");
  auto fail = [&](const std::string& what) {
    const int e = errno;
    close(fd_);
    fd_ = -1;
    throw BusError("socketcan " + ifname + ": " + what + ": " + std::strerror(e));
  };
  // Error frames (bus-off, passive, restarted) and our own frames, so the
  // node sees the bus as every other backend shows it.
  can_err_mask_t mask = CAN_ERR_MASK;
  if (setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &mask, sizeof mask) != 0)
    fail("CAN_RAW_ERR_FILTER");
  int one = 1;
  if (setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &one, sizeof one) != 0)
    fail("CAN_RAW_RECV_OWN_MSGS");
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, ifname.c_str(), IFNAMSIZ - 1);
  if (ioctl(fd_, SIOCGIFINDEX, &ifr) != 0) fail("no such interface");
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) fail("bind");
}

SocketCanBus::~SocketCanBus() {
  if (fd_ >= 0) close(fd_);
}

bool SocketCanBus::send(const Frame& f) {
  if (f.len > 8 || state_ == BusState::BusOff) {
    ++counters_.tx_dropped;
    return false;
  }
  can_frame cf{};
  cf.can_id = f.id;
  cf.can_dlc = f.len;
  std::memcpy(cf.data, f.data.data(), f.len);
  if (::write(fd_, &cf, sizeof cf) != static_cast<ssize_t>(sizeof cf)) {
    ++counters_.tx_dropped;  // ENOBUFS: the interface queue is full
    return false;
  }
  ++counters_.tx;
  return true;
}

bool SocketCanBus::receive(Frame& f) {
  for (int tries = 0; tries < 256; ++tries) {
    can_frame cf{};
    const ssize_t n = ::read(fd_, &cf, sizeof cf);
    if (n < 0) return false;
    if (n != static_cast<ssize_t>(sizeof cf) || cf.can_dlc > 8) {
      ++counters_.rx_bad;  // a CAN FD frame or a short read
      continue;
    }
    f.id = cf.can_id;
    f.len = cf.can_dlc;
    std::memcpy(f.data.data(), cf.data, 8);
    if (f.error()) {
      ++counters_.error_frames;
      state_ = bus_state_after(state_, f);
    } else if (state_ == BusState::BusOff) {
      state_ = BusState::ErrorActive;  // traffic again: the controller restarted
    }
    ++counters_.rx;
    return true;
  }
  return false;
}

}  // namespace plc::can

// Linux SocketCAN (CAN_RAW) on an interface such as can0:
//   ip link set can0 up type can bitrate 500000 restart-ms 100
// Error frames are received (CAN_RAW_ERR_FILTER = all) and tracked into
// state(): bus-off, error-passive, and back to error-active when the
// controller restarts. Own transmissions are echoed (CAN_RAW_RECV_OWN_MSGS).
#pragma once

#include <string>

#include "plc/can/bus.hpp"

namespace plc::can {

class SocketCanBus final : public Bus {
 public:
  explicit SocketCanBus(const std::string& ifname);  // throws BusError
  ~SocketCanBus() override;
  bool send(const Frame& f) override;
  bool receive(Frame& f) override;
  int fd() const override { return fd_; }
  BusState state() const override { return state_; }
  const BusCounters& counters() const override { return counters_; }

 private:
  int fd_ = -1;
  BusState state_ = BusState::ErrorActive;
  BusCounters counters_;
};

// The bus state after error frame `err` (linux/can/error.h classes).
BusState bus_state_after(BusState before, const Frame& err);

}  // namespace plc::can

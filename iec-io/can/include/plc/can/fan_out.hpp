// Several nodes in one process on one bus connection: pump() reads the
// connection and hands every frame to every node (each a Bus of its own);
// a node's send() goes out on the connection, and the bus echoes it back to
// all of them, as on a wire. dnslave hosts its slaves this way.
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <vector>

#include "plc/can/bus.hpp"

namespace plc::can {

class FanOut {
 public:
  explicit FanOut(Bus& inner) : inner_(inner) {}
  std::unique_ptr<Bus> node();
  // Reads every pending frame into the nodes' queues; `tap` (optional) sees
  // each frame once (a pcap capture).
  void pump(const std::function<void(const Frame&)>& tap = {});
  [[nodiscard]] int fd() const { return inner_.fd(); }

 private:
  class Node;
  Bus& inner_;
  std::vector<Node*> nodes_;
};

}  // namespace plc::can

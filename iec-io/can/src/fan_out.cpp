#include "plc/can/fan_out.hpp"

#include <algorithm>

namespace plc::can {

class FanOut::Node final : public Bus {
 public:
  explicit Node(FanOut& owner) : owner_(owner) {}
  ~Node() override {
    auto& v = owner_.nodes_;
    v.erase(std::remove(v.begin(), v.end(), this), v.end());
  }
  bool send(const Frame& f) override { return owner_.inner_.send(f); }
  bool receive(Frame& f) override {
    if (queue_.empty()) return false;
    f = queue_.front();
    queue_.pop_front();
    return true;
  }
  BusState state() const override { return owner_.inner_.state(); }
  const BusCounters& counters() const override { return owner_.inner_.counters(); }
  void push(const Frame& f) {
    if (queue_.size() < 4096) queue_.push_back(f);
  }

 private:
  FanOut& owner_;
  std::deque<Frame> queue_;
};

std::unique_ptr<Bus> FanOut::node() {
  auto n = std::make_unique<Node>(*this);
  nodes_.push_back(n.get());
  return n;
}

void FanOut::pump(const std::function<void(const Frame&)>& tap) {
  Frame f;
  for (int n = 0; n < 4096 && inner_.receive(f); ++n) {
    if (tap) tap(f);
    for (Node* node : nodes_) node->push(f);
  }
}

}  // namespace plc::can

#include "plc/profinet/link/memory_udp.hpp"

#include "memory_segment.hpp"

namespace plc::profinet {

namespace {

struct Source {
  Ipv4 ip;
  std::uint16_t port = 0;
};

std::uint64_t key_of(Ipv4 ip, std::uint16_t port) {
  return std::uint64_t(ip.host_order) << 16 | port;
}

struct IpLess {
  bool operator()(Ipv4 a, Ipv4 b) const { return a.host_order < b.host_order; }
};

}  // namespace

struct MemoryUdp::Impl : detail::MemorySegment<Ipv4, Source, IpLess> {
  Impl() : MemorySegment(kMaxDatagram) {}
};

namespace {

class MemoryUdpPort final : public UdpPort {
 public:
  MemoryUdpPort(std::shared_ptr<MemoryUdp::Impl> net, Ipv4 ip, std::uint16_t port)
      : net_(std::move(net)), ip_(ip), port_(port), key_(key_of(ip, port)) {
    std::lock_guard lock(net_->mutex);
    if (net_->endpoints.count(key_) != 0)
      throw LinkError("memory UDP network: " + to_string(ip) + ":" + std::to_string(port) +
                      " is already bound");
    ep_ = &net_->add(key_, ip, &counters_);
    net_->set_own_only(*ep_, true);  // datagrams to its ip:port only
  }
  ~MemoryUdpPort() override {
    std::lock_guard lock(net_->mutex);
    net_->remove(key_);
  }
  Ipv4 local_ip() const override { return ip_; }
  const std::atomic<std::size_t>* queued_count() const override { return &ep_->queued; }
  std::uint16_t local_port() const override { return port_; }
  bool send_to(Ipv4 ip, std::uint16_t port, std::span<const std::uint8_t> data) override {
    if (data.size() > kMaxDatagram) {
      counters_.send_failed.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    // The port bound to ip:port, else one bound to 0.0.0.0:port.
    const std::uint64_t exact = key_of(ip, port), any = key_of(Ipv4{}, port);
    bool has_exact = false;
    {
      Seg::Lock lock(*net_);
      has_exact = net_->endpoints.count(exact) != 0;
    }
    const std::uint64_t target = has_exact ? exact : any;
    const bool ok = net_->send(ip_, key_, data, Source{ip_, port_}, target,
                               [&](std::uint64_t k, auto&) { return k == target; });
    (ok ? counters_.sent : counters_.send_failed).fetch_add(1, std::memory_order_relaxed);
    return ok;
  }
  std::size_t receive_from(std::span<std::uint8_t> buf, Ipv4& ip, std::uint16_t& port,
                           std::chrono::nanoseconds timeout) override {
    // Polled every tick, and mostly nothing is there: the look first, the
    // rest out of line.
    if (timeout.count() <= 0 && ep_->queued.load(std::memory_order_relaxed) == 0) return 0;
    return take_from(buf, ip, port, timeout);
  }

 private:
  [[gnu::noinline]] std::size_t take_from(std::span<std::uint8_t> buf, Ipv4& ip,
                                          std::uint16_t& port, std::chrono::nanoseconds timeout) {
    Source src;
    const std::size_t n = net_->take(*ep_, buf, timeout, &src);
    if (n > 0) {
      ip = src.ip;
      port = src.port;
    }
    return n;
  }
  using Seg = detail::MemorySegment<Ipv4, Source, IpLess>;
  std::shared_ptr<MemoryUdp::Impl> net_;
  Ipv4 ip_;
  std::uint16_t port_;
  std::uint64_t key_;
  Seg::Endpoint* ep_ = nullptr;  // ours on the network, while we live
};

}  // namespace

MemoryUdp::MemoryUdp() : impl_(std::make_shared<Impl>()) {}

std::unique_ptr<UdpPort> MemoryUdp::port(Ipv4 ip, std::uint16_t port) {
  return std::make_unique<MemoryUdpPort>(impl_, ip, port);
}

void MemoryUdp::drop_next(Ipv4 from, int n) { impl_->drop_next(from, n); }
void MemoryUdp::delay_next(Ipv4 from, int n, std::chrono::nanoseconds d) {
  impl_->delay_next(from, n, d);
}
void MemoryUdp::set_link_up(Ipv4 port, bool up) { impl_->set_down(port, !up); }
void MemoryUdp::set_single_threaded(bool yes) {
  impl_->single_threaded.store(yes, std::memory_order_relaxed);
}
bool MemoryUdp::single_threaded() const {
  return impl_->single_threaded.load(std::memory_order_relaxed);
}
void MemoryUdp::set_time(std::chrono::nanoseconds now) { impl_->set_time(now); }
std::chrono::nanoseconds MemoryUdp::time() const { return impl_->time(); }
std::uint64_t MemoryUdp::datagrams_carried() const { return impl_->carried_count(); }

}  // namespace plc::profinet

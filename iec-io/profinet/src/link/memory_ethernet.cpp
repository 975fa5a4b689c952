#include "plc/profinet/link/memory_ethernet.hpp"

#include <bit>
#include <cstring>

#include "memory_segment.hpp"

namespace plc::profinet {

namespace {

std::uint64_t key_of(const Mac& m) {
  std::uint64_t k = 0;
  for (auto b : m) k = k << 8 | b;
  return k;
}

// key_of() of the destination MAC at the start of a frame (frame.size() >=
// 14: eight bytes can be read): one load, not six.
std::uint64_t destination_key(std::span<const std::uint8_t> frame) {
  std::uint64_t v = 0;
  std::memcpy(&v, frame.data(), 8);
  if constexpr (std::endian::native == std::endian::little) return __builtin_bswap64(v) >> 16;
  return v >> 16;
}

struct NoExtra {};

// Whether the frame's destination is `mac` (every frame is checked against
// every port on the general path).
bool addressed_to(std::span<const std::uint8_t> frame, const Mac& mac) {  // frame.size() >= 6
  return same_mac(frame.data(), mac.data());
}

}  // namespace

struct MemoryEthernet::Impl : detail::MemorySegment<Mac, NoExtra> {
  Impl() : MemorySegment(kMaxFrameLength) {}
  std::uint64_t next_mac = 1;
};

namespace {

class MemoryEthernetPort final : public EthernetPort {
 public:
  MemoryEthernetPort(std::shared_ptr<MemoryEthernet::Impl> hub, Mac mac, bool promiscuous)
      : hub_(std::move(hub)), mac_(mac), key_(key_of(mac)) {
    std::lock_guard lock(hub_->mutex);
    if (hub_->endpoints.count(key_) != 0)
      throw LinkError("memory hub: MAC " + to_string(mac) + " is already on the hub");
    ep_ = &hub_->add(key_, mac, &counters_);
    hub_->set_own_only(*ep_, !promiscuous);
  }
  ~MemoryEthernetPort() override {
    std::lock_guard lock(hub_->mutex);
    hub_->remove(key_);
  }
  Mac mac() const override { return mac_; }
  bool send(std::span<const std::uint8_t> frame) override {
    if (frame.size() < 14 || frame.size() > kMaxFrameLength) {
      counters_.send_failed.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    // Every port takes only PROFINET frames (as the raw port's binding
    // does): others are carried but reach nobody.
    const bool deliver = is_profinet(frame);
    const bool group = (frame[0] & 0x01) != 0;  // multicast or broadcast
    // A unicast PROFINET frame: an own_only port takes it only under its
    // destination's key (addressed_to() is key equality).
    const std::uint64_t target = deliver && !group ? destination_key(frame) : Seg::kEveryone;
    const bool ok = hub_->send_short(key_, frame, NoExtra{}, target) ||
                    send_locked(frame, deliver, group, target);
    (ok ? counters_.sent : counters_.send_failed).fetch_add(1, std::memory_order_relaxed);
    return ok;
  }
  std::size_t receive(std::span<std::uint8_t> buf, std::chrono::nanoseconds timeout) override {
    return hub_->take(*ep_, buf, timeout, nullptr);
  }
  const std::atomic<std::size_t>* queued_count() const override { return &ep_->queued; }
  // The frame in the hub's buffer, no copy (memory_segment.hpp view()).
  std::span<const std::uint8_t> receive_view(std::span<std::uint8_t> buf,
                                             std::chrono::nanoseconds timeout) override {
    return hub_->view(*ep_, buf.size(), timeout, nullptr);
  }

 private:
  using Seg = detail::MemorySegment<Mac, NoExtra>;
  // The rest of send() (MemorySegment::send_locked()), out of line: the
  // short path then builds no filter.
  [[gnu::noinline]] bool send_locked(std::span<const std::uint8_t> frame, bool deliver, bool group,
                                     std::uint64_t target) {
    const auto to = [&](std::uint64_t, const Seg::Endpoint& ep) {
      return deliver && (!ep.own_only || group || addressed_to(frame, ep.address));
    };
    return hub_->send_locked(mac_, key_, frame, NoExtra{}, target, to);
  }
  static bool is_profinet(std::span<const std::uint8_t> f) {  // f.size() >= 14
    auto type_at = [&](std::size_t o) { return std::uint16_t(f[o] << 8 | f[o + 1]); };
    if (type_at(12) == kEtherTypeProfinet) return true;
    return f.size() >= 18 && type_at(12) == kEtherTypeVlan && type_at(16) == kEtherTypeProfinet;
  }
  std::shared_ptr<MemoryEthernet::Impl> hub_;
  Mac mac_;
  std::uint64_t key_;
  Seg::Endpoint* ep_ = nullptr;  // ours in the hub, while we live
};

}  // namespace

MemoryEthernet::MemoryEthernet() : impl_(std::make_shared<Impl>()) {}

std::unique_ptr<EthernetPort> MemoryEthernet::port(Mac mac, bool promiscuous) {
  if (mac == Mac{}) {
    std::lock_guard lock(impl_->mutex);
    do {
      const std::uint64_t n = impl_->next_mac++;
      mac = {
          0x02,           0x00, std::uint8_t(n >> 24), std::uint8_t(n >> 16), std::uint8_t(n >> 8),
          std::uint8_t(n)};
    } while (impl_->endpoints.count(key_of(mac)) != 0);
  }
  return std::make_unique<MemoryEthernetPort>(impl_, mac, promiscuous);
}

void MemoryEthernet::drop_next(const Mac& from, int n) { impl_->drop_next(from, n); }
void MemoryEthernet::delay_next(const Mac& from, int n, std::chrono::nanoseconds d) {
  impl_->delay_next(from, n, d);
}
void MemoryEthernet::set_link_up(const Mac& port, bool up) { impl_->set_down(port, !up); }
void MemoryEthernet::set_single_threaded(bool yes) {
  impl_->single_threaded.store(yes, std::memory_order_relaxed);
}
bool MemoryEthernet::single_threaded() const {
  return impl_->single_threaded.load(std::memory_order_relaxed);
}
void MemoryEthernet::set_time(std::chrono::nanoseconds now) { impl_->set_time(now); }
std::chrono::nanoseconds MemoryEthernet::time() const { return impl_->time(); }
std::uint64_t MemoryEthernet::frames_carried() const { return impl_->carried_count(); }

}  // namespace plc::profinet

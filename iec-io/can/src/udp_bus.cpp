#include "plc/can/udp_bus.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "plc/realtime_thread.hpp"
#include "plc/thread_guard.hpp"

namespace plc::can {

namespace {

constexpr std::int64_t kKeepAliveNs = 1'000'000'000;
constexpr std::int64_t kForgetNs = 5'000'000'000;

sockaddr_in resolve(const std::string& host, std::uint16_t port) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* res = nullptr;
  if (getaddrinfo(host.c_str(), nullptr, &hints, &res) != 0 || !res)
    throw BusError("udp: cannot resolve host '" + host + "'");
  sockaddr_in a{};
  std::memcpy(&a, res->ai_addr, sizeof a);
  freeaddrinfo(res);
  a.sin_port = htons(port);
  return a;
}

int udp_socket() {
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) throw BusError(std::string("udp: socket: ") + std::strerror(errno));
  return fd;
}

}  // namespace

UdpBus::UdpBus(const std::string& host, std::uint16_t port) {
  const sockaddr_in hub = resolve(host, port);
  fd_ = udp_socket();
  if (connect(fd_, reinterpret_cast<const sockaddr*>(&hub), sizeof hub) != 0) {
    const int e = errno;
    close(fd_);
    throw BusError("udp: connect to " + host + ":" + std::to_string(port) + ": " +
                   std::strerror(e));
  }
  keep_alive(true);
}

UdpBus::~UdpBus() {
  if (fd_ >= 0) close(fd_);
}

void UdpBus::keep_alive(bool force) {
  const std::int64_t now = mono_ns();
  if (!force && now - last_tx_ns_ < kKeepAliveNs) return;
  std::array<std::uint8_t, udp::kHeaderSize> d{};
  const std::size_t n = udp::encode(seq_++, {}, d);
  // A hub that is not up yet refuses (ECONNREFUSED); the next keep-alive retries.
  (void)::send(fd_, d.data(), n, MSG_DONTWAIT);
  last_tx_ns_ = now;
}

bool UdpBus::send(const Frame& f) {
  std::array<std::uint8_t, udp::kHeaderSize + udp::kMaxFrameSize> d{};
  const std::size_t n = udp::encode(seq_++, {&f, 1}, d);
  if (n == 0 || ::send(fd_, d.data(), n, MSG_DONTWAIT) != static_cast<ssize_t>(n)) {
    ++counters_.tx_dropped;
    return false;
  }
  last_tx_ns_ = mono_ns();
  ++counters_.tx;
  return true;
}

bool UdpBus::receive(Frame& f) {
  keep_alive(false);
  // Bounded: at most a socket buffer's worth of bad datagrams per call.
  for (int tries = 0; tries < 256; ++tries) {
    if (pending_pos_ < pending_n_) {
      f = pending_[pending_pos_++];
      ++counters_.rx;
      if (f.error()) ++counters_.error_frames;
      return true;
    }
    std::array<std::uint8_t, udp::kMaxDatagram + 1> d{};
    const ssize_t n = ::recv(fd_, d.data(), d.size(), MSG_DONTWAIT);
    if (n < 0) return false;  // EAGAIN, or ECONNREFUSED while the hub is away
    const int k = udp::decode({d.data(), static_cast<std::size_t>(n)}, pending_);
    if (k < 0) {
      ++counters_.rx_bad;
      continue;
    }
    pending_n_ = static_cast<std::size_t>(k);
    pending_pos_ = 0;
  }
  return false;
}

UdpHub::UdpHub(const std::string& host, std::uint16_t port) {
  sockaddr_in a = resolve(host, port);
  fd_ = udp_socket();
  if (bind(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    const int e = errno;
    close(fd_);
    throw BusError("udp hub: bind " + host + ":" + std::to_string(port) + ": " + std::strerror(e));
  }
  socklen_t len = sizeof a;
  getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
  port_ = ntohs(a.sin_port);
  if (pipe2(wake_, O_CLOEXEC | O_NONBLOCK) != 0) {
    close(fd_);
    throw BusError("udp hub: pipe failed");
  }
  // A failed hub forwards nothing more: every node on it sees a silent bus
  // and times out as it would on a cut cable.
  thread_ = std::thread([this] {
    run_guarded(
        "can udp hub", [this] { run(); }, [](std::string_view) {});
  });
}

UdpHub::~UdpHub() {
  const char c = 1;
  (void)!write(wake_[1], &c, 1);
  if (thread_.joinable()) thread_.join();
  close(fd_);
  close(wake_[0]);
  close(wake_[1]);
}

void UdpHub::run() {
  struct Peer {
    sockaddr_in addr;
    std::int64_t heard_ns;
  };
  constexpr std::size_t kMaxPeers = 64;
  std::vector<Peer> peers;
  peers.reserve(kMaxPeers);
  std::array<Frame, udp::kMaxFramesPerDatagram> scratch{};
  for (;;) {
    pollfd p[2] = {{fd_, POLLIN, 0}, {wake_[0], POLLIN, 0}};
    if (poll(p, 2, 1000) < 0 && errno != EINTR) return;
    if (p[1].revents) return;
    for (int burst = 0; burst < 1024; ++burst) {
      std::array<std::uint8_t, udp::kMaxDatagram + 1> d{};
      sockaddr_in from{};
      socklen_t flen = sizeof from;
      const ssize_t n = recvfrom(fd_, d.data(), d.size(), MSG_DONTWAIT,
                                 reinterpret_cast<sockaddr*>(&from), &flen);
      if (n < 0) break;
      const std::int64_t now = mono_ns();
      const int k = udp::decode({d.data(), static_cast<std::size_t>(n)}, scratch);
      if (k < 0) {
        ++rejected_;
        continue;
      }
      bool known = false;
      for (Peer& q : peers)
        if (q.addr.sin_addr.s_addr == from.sin_addr.s_addr && q.addr.sin_port == from.sin_port) {
          q.heard_ns = now;
          known = true;
        }
      std::erase_if(peers, [&](const Peer& q) { return now - q.heard_ns > kForgetNs; });
      if (!known && peers.size() < kMaxPeers) peers.push_back({from, now});
      if (k == 0) continue;  // keep-alive: not forwarded
      // Counted before it goes out: a node that has received it must
      // never read a count without it.
      ++forwarded_;
      for (const Peer& q : peers)
        (void)sendto(fd_, d.data(), static_cast<std::size_t>(n), MSG_DONTWAIT,
                     reinterpret_cast<const sockaddr*>(&q.addr), sizeof q.addr);
    }
  }
}

}  // namespace plc::can

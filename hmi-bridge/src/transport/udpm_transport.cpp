#include "plc/hmi/udpm_transport.hpp"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "plc/hmi/udpm_wire.hpp"
#include "plc/hmi/utime.hpp"

namespace plc::hmi {

namespace {

std::int64_t mono_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::string dotted(std::uint32_t host_order) {
  in_addr a{};
  a.s_addr = htonl(host_order);
  char b[INET_ADDRSTRLEN] = "";
  ::inet_ntop(AF_INET, &a, b, sizeof b);
  return b;
}

enum class Read { Message, Consumed, Empty, Error };

}  // namespace

UdpmTransport::UdpmTransport(const LcmUrl& url, const UdpmLimits& limits)
    : url_(url),
      receiver_(limits, [this](std::string_view channel) { return subscribed(channel); }),
      buf_(udpm::kMaxDatagram) {
  dest_.sin_family = AF_INET;
  dest_.sin_addr.s_addr = htonl(url.group);
  dest_.sin_port = htons(url.port);
}

UdpmTransport::~UdpmTransport() {
  if (send_fd_ >= 0) ::close(send_fd_);
  if (recv_fd_ >= 0) ::close(recv_fd_);
}

std::unique_ptr<UdpmTransport> UdpmTransport::open(const LcmUrl& url, const UdpmLimits& limits,
                                                   std::string& error) {
  std::unique_ptr<UdpmTransport> t(new UdpmTransport(url, limits));
  const std::string where = "udpm://" + dotted(url.group) + ":" + std::to_string(url.port);
  auto fail = [&](const std::string& what) {
    error = where + ": " + what + ": " + std::strerror(errno);
    return nullptr;
  };
  // As liblcm (lcm_udpm_create): a connect() that finds no route says so
  // before anything else is set up.
  {
    const int probe = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (probe < 0) return fail("socket");
    const int rc = ::connect(probe, reinterpret_cast<const sockaddr*>(&t->dest_), sizeof t->dest_);
    const int err = errno;
    ::close(probe);
    if (rc != 0) {
      errno = err;
      error = where + ": no route to " + dotted(url.group) + " (" + std::strerror(err) +
              "); udpm needs a multicast route: ip route add 224.0.0.0/4 dev lo";
      return nullptr;
    }
  }
  const int one = 1, ttl = url.ttl;
  t->send_fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (t->send_fd_ < 0) return fail("send socket");
  if (::setsockopt(t->send_fd_, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl) != 0)
    return fail("IP_MULTICAST_TTL");
  if (::setsockopt(t->send_fd_, IPPROTO_IP, IP_MULTICAST_LOOP, &one, sizeof one) != 0)
    return fail("IP_MULTICAST_LOOP");

  t->recv_fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (t->recv_fd_ < 0) return fail("receive socket");
  if (::setsockopt(t->recv_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0)
    return fail("SO_REUSEADDR");
  // Not granted in full: the kernel caps it (liblcm warns and carries on).
  const int want = url.recv_buf_size > 0 ? url.recv_buf_size : kDefaultRecvBufSize;
  (void)::setsockopt(t->recv_fd_, SOL_SOCKET, SO_RCVBUF, &want, sizeof want);
  socklen_t len = sizeof t->recv_buf_size_;
  (void)::getsockopt(t->recv_fd_, SOL_SOCKET, SO_RCVBUF, &t->recv_buf_size_, &len);
  if (::setsockopt(t->recv_fd_, SOL_SOCKET, SO_TIMESTAMP, &one, sizeof one) != 0)
    return fail("SO_TIMESTAMP");
  if (::bind(t->recv_fd_, reinterpret_cast<const sockaddr*>(&t->dest_), sizeof t->dest_) != 0)
    return fail("bind");
  ip_mreq mreq{};
  mreq.imr_multiaddr = t->dest_.sin_addr;
  mreq.imr_interface.s_addr = htonl(INADDR_ANY);
  if (::setsockopt(t->recv_fd_, IPPROTO_IP, IP_ADD_MEMBERSHIP, &mreq, sizeof mreq) != 0)
    return fail("joining the group (IP_ADD_MEMBERSHIP)");
  return t;
}

bool UdpmTransport::publish(const std::string& channel, const void* data, std::size_t size) {
  const std::span<const std::uint8_t> payload(static_cast<const std::uint8_t*>(data), size);
  if (size > receiver_.limits().max_message_bytes || udpm::datagram_count(channel, size) == 0) {
    std::lock_guard<std::mutex> lock(counters_mu_);
    ++too_large_;
    return false;
  }
  std::lock_guard<std::mutex> send(send_mu_);
  const std::uint32_t seqno = seqno_++;  // as liblcm: counted whether or not it went out
  const std::size_t want = udpm::datagram_count(channel, size);
  const std::size_t sent =
      udpm::for_each_datagram(channel, payload, seqno, [&](const udpm::Datagram& d) {
        iovec iov[2] = {{const_cast<std::uint8_t*>(d.head.data()), d.head_size},
                        {const_cast<std::uint8_t*>(d.body.data()), d.body.size()}};
        msghdr msg{};
        msg.msg_name = &dest_;
        msg.msg_namelen = sizeof dest_;
        msg.msg_iov = iov;
        msg.msg_iovlen = 2;
        for (int attempt = 0; attempt < 3; ++attempt) {  // bounded retry after a signal
          const ssize_t n = ::sendmsg(send_fd_, &msg, MSG_NOSIGNAL);
          if (n >= 0) return std::size_t(n) == d.size();
          if (errno != EINTR) return false;
        }
        return false;
      });
  if (sent == want) return true;
  std::lock_guard<std::mutex> lock(counters_mu_);
  ++send_errors_;
  return false;
}

int UdpmTransport::read_one() {
  sockaddr_in from{};
  iovec iov{buf_.data(), buf_.size()};
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timeval))];
  msghdr msg{};
  msg.msg_name = &from;
  msg.msg_namelen = sizeof from;
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof control;
  const ssize_t n = ::recvmsg(recv_fd_, &msg, MSG_DONTWAIT);
  if (n < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return int(Read::Empty);
    std::lock_guard<std::mutex> lock(counters_mu_);
    ++recv_errors_;
    return int(Read::Error);
  }
  std::int64_t recv_utime = 0;
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c))
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMP) {
      timeval tv{};
      std::memcpy(&tv, CMSG_DATA(c), sizeof tv);
      recv_utime = std::int64_t(tv.tv_sec) * 1'000'000 + tv.tv_usec;
    }
  if (!recv_utime) recv_utime = utime_now();
  const std::uint64_t sender =
      std::uint64_t(ntohl(from.sin_addr.s_addr)) << 16 | ntohs(from.sin_port);
  std::optional<UdpmMessage> m;
  {
    std::lock_guard<std::mutex> lock(counters_mu_);
    if (msg.msg_flags & MSG_TRUNC) {
      receiver_.count_truncated();
      return int(Read::Consumed);
    }
    m = receiver_.take({buf_.data(), std::size_t(n)}, sender, mono_us(), recv_utime);
  }
  if (!m) return int(Read::Consumed);
  const ReceiveBuffer rb{m->data.data(), m->data.size(), m->recv_utime};
  TransportCounters thrown;
  dispatch(m->channel, rb, thrown);
  std::lock_guard<std::mutex> lock(counters_mu_);
  handler_exceptions_ += thrown.handler_exceptions;
  return int(Read::Message);
}

int UdpmTransport::handle_timeout(int timeout_ms) {
  const std::int64_t deadline = mono_us() + std::int64_t(std::max(timeout_ms, 0)) * 1000;
  // Bounded by the deadline; each round reads at most 256 datagrams, so a
  // flood of junk cannot hold a zero-timeout call.
  for (;;) {
    for (int i = 0; i < 256; ++i) {
      const int r = read_one();
      if (r == int(Read::Message)) return 1;
      if (r == int(Read::Error)) return -1;
      if (r == int(Read::Empty)) break;
    }
    const std::int64_t left_us = deadline - mono_us();
    if (left_us <= 0) return 0;
    pollfd p{recv_fd_, POLLIN, 0};
    const int rc = ::poll(&p, 1, int((left_us + 999) / 1000));
    if (rc < 0 && errno != EINTR) return -1;
  }
}

TransportCounters UdpmTransport::counters() const {
  std::lock_guard<std::mutex> lock(counters_mu_);
  TransportCounters c = receiver_.counters();
  c.recv_errors += recv_errors_;
  c.send_errors += send_errors_;
  c.too_large_to_send += too_large_;
  c.handler_exceptions += handler_exceptions_;
  return c;
}

}  // namespace plc::hmi

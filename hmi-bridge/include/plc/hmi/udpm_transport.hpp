// udpm://ADDR:PORT?ttl=N: LCM over UDP multicast, on the wire exactly as
// liblcm 1.3.1 (udpm_wire.hpp), received through the bounded UdpmReceiver.
//
// Sockets as lcm_udpm.c sets them up on Linux: a send socket with
// IP_MULTICAST_TTL = ttl and IP_MULTICAST_LOOP on (other processes of this
// host hear us); a receive socket with SO_REUSEADDR (several processes
// share the port; liblcm sets SO_REUSEPORT on macOS and FreeBSD only, and
// Linux shares a UDP port between sockets that all set SO_REUSEADDR), the
// kernel's receive time (SO_TIMESTAMP), joined to the group on the
// interface of the route to it (INADDR_ANY, as liblcm). Unlike liblcm it
// binds to the group address rather than INADDR_ANY: datagrams sent to the
// port on any other address of the host (unicast) never reach it.
//
// There is no receive thread: handle_timeout reads the socket, so the
// kernel's buffer is the queue. recv_buf_size, when the url gives none,
// asks for 2 MiB (the kernel caps it at net.core.rmem_max) so that a
// fragmented message waits whole while a handler runs.
#pragma once

#include <netinet/in.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "plc/hmi/lcm_url.hpp"
#include "plc/hmi/transport.hpp"
#include "plc/hmi/udpm_receiver.hpp"

namespace plc::hmi {

class UdpmTransport final : public Transport {
 public:
  static constexpr int kDefaultRecvBufSize = 2 << 20;

  // nullptr and `error` when a socket cannot be set up (no multicast route:
  // what to do about it is in the error).
  static std::unique_ptr<UdpmTransport> open(const LcmUrl& url, const UdpmLimits& limits,
                                             std::string& error);
  ~UdpmTransport() override;
  UdpmTransport(const UdpmTransport&) = delete;
  UdpmTransport& operator=(const UdpmTransport&) = delete;

  using Transport::publish;
  bool publish(const std::string& channel, const void* data, std::size_t size) override;
  int handle_timeout(int timeout_ms) override;
  [[nodiscard]] TransportCounters counters() const override;

  // The kernel's receive buffer as granted (getsockopt SO_RCVBUF).
  [[nodiscard]] int recv_buf_size() const { return recv_buf_size_; }

 private:
  UdpmTransport(const LcmUrl& url, const UdpmLimits& limits);
  // Reads and takes one waiting datagram: 1 a message was handed to its
  // subscribers, 0 none (nothing waiting, or it completed nothing), -1 a
  // socket error.
  int read_one();

  LcmUrl url_;
  sockaddr_in dest_{};
  int send_fd_ = -1, recv_fd_ = -1;
  int recv_buf_size_ = 0;
  std::mutex send_mu_;  // publish from any thread: one message's fragments together
  std::uint32_t seqno_ = 0;
  mutable std::mutex counters_mu_;  // the receiver's counters against counters()
  UdpmReceiver receiver_;
  std::uint64_t send_errors_ = 0, too_large_ = 0, handler_exceptions_ = 0, recv_errors_ = 0;
  std::vector<std::uint8_t> buf_;  // one datagram
};

}  // namespace plc::hmi

// Waiting for a descriptor with a nanosecond timeout (ppoll), shared by the
// socket transports. Private to src/link.
#pragma once

#include <poll.h>

#include <cerrno>
#include <chrono>
#include <ctime>

namespace plc::profinet::detail {

// true when `fd` is readable within `timeout` (0 = just look). An EINTR
// ends the wait early (the caller's loop comes back).
inline bool wait_readable(int fd, std::chrono::nanoseconds timeout) {
  pollfd p{fd, POLLIN, 0};
  const auto t = timeout.count() < 0 ? 0 : timeout.count();
  const timespec ts{static_cast<time_t>(t / 1'000'000'000), static_cast<long>(t % 1'000'000'000)};
  return ::ppoll(&p, 1, &ts, nullptr) > 0 && (p.revents & POLLIN) != 0;
}

}  // namespace plc::profinet::detail

#include "plc/hmi/web/login_limiter.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <cstring>
#include <utility>

namespace plc::hmi::web {

std::chrono::seconds LoginLimiter::locked_for(std::string_view address,
                                              Clock::time_point now) const {
  const Entry* e = find(address);
  if (!e || now >= e->locked_until) return std::chrono::seconds(0);
  // Rounded up: a client that waits Retry-After seconds finds the lock gone.
  const auto left = e->locked_until - now;
  const auto whole = std::chrono::duration_cast<std::chrono::seconds>(left);
  return whole + std::chrono::seconds(whole < left ? 1 : 0);
}

void LoginLimiter::failed(std::string_view address, Clock::time_point now) {
  Entry& e = slot_for(address, now);
  e.last_failure = now;
  e.recent[std::size_t(e.next)] = now;
  e.next = (e.next + 1) % kMaxFailures;
  e.failures = std::min(e.failures + 1, kMaxFailures);
  // Full, and its oldest (the slot written next) within kWindow: locked.
  if (e.failures == kMaxFailures && now - e.recent[std::size_t(e.next)] < kWindow) {
    e.locked_until = now + kLockout;
    e.failures = 0;
  }
}

void LoginLimiter::succeeded(std::string_view address) {
  if (Entry* e = find(address)) *e = Entry{};
}

std::size_t LoginLimiter::size() const {
  return std::size_t(std::count_if(entries_.begin(), entries_.end(),
                                   [](const Entry& e) { return !e.address.empty(); }));
}

LoginLimiter::Entry* LoginLimiter::find(std::string_view address) {
  return const_cast<Entry*>(std::as_const(*this).find(address));
}

const LoginLimiter::Entry* LoginLimiter::find(std::string_view address) const {
  if (address.empty()) return nullptr;
  for (const Entry& e : entries_)
    if (e.address == address) return &e;
  return nullptr;
}

LoginLimiter::Entry& LoginLimiter::slot_for(std::string_view address, Clock::time_point now) {
  if (Entry* e = find(address)) return *e;
  // A free slot, else the entry to forget: one whose lock has run out (or
  // that never locked) before one still locked, the oldest last failure
  // first among them.
  Entry* victim = &entries_.front();
  auto rank = [now](const Entry& e) {
    return std::make_pair(!e.address.empty() && now < e.locked_until, e.last_failure);
  };
  for (Entry& e : entries_) {
    if (e.address.empty()) {
      victim = &e;
      break;
    }
    if (rank(e) < rank(*victim)) victim = &e;
  }
  *victim = Entry{};
  victim->address.assign(address);
  return *victim;
}

std::string address_key(std::string_view address) {
  const std::string text(address);
  in6_addr a6{};
  if (::inet_pton(AF_INET6, text.c_str(), &a6) != 1) return text;
  char out[INET6_ADDRSTRLEN] = "";
  const unsigned char* b = a6.s6_addr;
  static constexpr unsigned char kMapped[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xff, 0xff};
  if (std::memcmp(b, kMapped, sizeof kMapped) == 0) {
    in_addr a4{};
    std::memcpy(&a4, b + 12, 4);
    ::inet_ntop(AF_INET, &a4, out, sizeof out);
    return out;
  }
  std::memset(a6.s6_addr + 8, 0, 8);
  ::inet_ntop(AF_INET6, &a6, out, sizeof out);
  return std::string(out) + "/64";
}

}  // namespace plc::hmi::web

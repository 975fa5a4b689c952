// The web HMI's limit on guessing the password (issue 27, security): after
// kMaxFailures failed logins from one client address within kWindow (any
// kWindow: the address's last kMaxFailures failures are kept), that
// address's logins are refused (HTTP 429 with Retry-After) for kLockout,
// before the password is even looked at: a guesser gets kMaxFailures tries
// per kLockout from each address it has. A login that succeeds forgets the
// address's failures.
//
// Bounded memory: a fixed table of kMaxAddresses; a new address takes the
// slot of the one whose last failure is oldest (an address that is locked
// out goes last). No network code and no clock of its own: the server
// passes the client's address (address_key()) and the time, so a test
// drives it without sleeping.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>

namespace plc::hmi::web {

class LoginLimiter {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kMaxFailures = 5;
  static constexpr std::chrono::seconds kWindow{60};
  static constexpr std::chrono::seconds kLockout{60};
  static constexpr std::size_t kMaxAddresses = 256;

  // How long `address` must wait before its next login is looked at: zero
  // when it may try now, else the whole seconds to send as Retry-After
  // (at least 1).
  [[nodiscard]] std::chrono::seconds locked_for(std::string_view address,
                                                Clock::time_point now) const;
  // A wrong password from `address`: the kMaxFailures-th within kWindow
  // locks it out for kLockout from now, and its count starts afresh.
  void failed(std::string_view address, Clock::time_point now);
  // A right one: the address's failures are forgotten.
  void succeeded(std::string_view address);
  // Addresses with failures on record (at most kMaxAddresses).
  [[nodiscard]] std::size_t size() const;

 private:
  struct Entry {
    std::string address;  // "" : a free slot
    // The last failures, a ring: recent[next] is the oldest once full.
    std::array<Clock::time_point, kMaxFailures> recent{};
    int failures = 0;  // in `recent`, at most kMaxFailures
    int next = 0;
    Clock::time_point last_failure{};
    Clock::time_point locked_until{};
  };
  Entry* find(std::string_view address);
  [[nodiscard]] const Entry* find(std::string_view address) const;
  Entry& slot_for(std::string_view address, Clock::time_point now);

  std::array<Entry, kMaxAddresses> entries_{};
};

// The key a client is counted under, from its address as text: an IPv4
// address as it is, an IPv4-mapped IPv6 address as its IPv4 address, any
// other IPv6 address as its /64 ("2001:db8:1:2::/64"): one host usually
// holds a whole /64, and counting its single addresses would give it 2^64
// times the tries. Text that is no address is its own key.
std::string address_key(std::string_view address);

}  // namespace plc::hmi::web

// Who may use the browser HMI: the login (a PBKDF2-SHA256 password hash or
// the HMI key), the session tokens it hands out, and the request checks
// (Host, Origin, CSRF token) every request passes (hmi-bridge/README.md
// "Web HMI"). No network code: the server asks, this answers.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plc::hmi::web {

inline constexpr int kDefaultPbkdf2Iterations = 200'000;

// "pbkdf2-sha256$ITERATIONS$SALT_HEX$HASH_HEX" of `password` with a fresh
// 16-byte salt (plchmi --hash-password).
std::string hash_password(std::string_view password, int iterations = kDefaultPbkdf2Iterations);
// Whether `password` matches `hash` (constant-time compare); false for a
// hash of another shape.
bool verify_password(std::string_view password, std::string_view hash);
// Whether `text` is the key's 64 hex digits (either case; constant-time).
bool verify_key_text(std::string_view text, const std::array<unsigned char, 32>& key);
// 32 random bytes as 64 hex digits.
std::string random_token();

struct Session {
  std::string csrf;  // the X-CSRF-Token every write must carry
  std::chrono::steady_clock::time_point last_used;
};

// The sessions logged in: at most kMax (the least recently used one goes),
// each expiring after `idle` without a request.
class Sessions {
 public:
  static constexpr std::size_t kMax = 64;
  explicit Sessions(std::chrono::seconds idle = std::chrono::hours(12)) : idle_(idle) {}
  // A new session: its token (the cookie) and CSRF token.
  std::pair<std::string, std::string> open(std::chrono::steady_clock::time_point now);
  // The session of cookie `token`, refreshed; nullptr when none or expired.
  const Session* find(std::string_view token, std::chrono::steady_clock::time_point now);
  void close(std::string_view token);
  [[nodiscard]] std::size_t size() const { return by_token_.size(); }

 private:
  std::chrono::seconds idle_;
  std::map<std::string, Session, std::less<>> by_token_;
};

// The value of cookie `name` in a Cookie header ("" when absent).
std::string cookie_value(std::string_view header, std::string_view name);

// The Host header values this server answers to: its address and port
// ("127.0.0.1:8080", "[::1]:8080"), and for a loopback address also
// "localhost:PORT". A name that resolves to us by DNS rebinding is none of
// them.
std::vector<std::string> allowed_hosts(const std::string& address, int port);
// Origin must be http(s)://HOST of the request's own (allowed) Host.
bool same_origin(std::string_view origin, std::string_view host, bool tls);

}  // namespace plc::hmi::web

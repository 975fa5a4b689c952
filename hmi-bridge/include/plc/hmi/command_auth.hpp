// The shared-key check of HMI commands: a counter that only goes up and an
// HMAC-SHA256 tag (libsodium crypto_auth_hmacsha256) over the command
// encoded with its tag all zero. Without a key every command passes this
// check (the access patterns still apply).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "softplc_hmi/command_t.hpp"

namespace plc::hmi {

using Key = std::array<std::uint8_t, 32>;

// Reads a key file: 64 hex digits (32 bytes), surrounding whitespace
// allowed. Error text in `err` when it cannot.
std::optional<Key> load_key(const std::string& path, std::string& err);

// Sets c.tag for `key` (the client side, plcctl).
void sign(softplc_hmi::command_t& c, const Key& key);

// Whether c.tag is right for `key` (constant-time compare).
bool verify(const softplc_hmi::command_t& c, const Key& key);

// The highest accepted counter per client: a command whose counter is not
// above it is a replay (or older than one already served).
class ReplayGuard {
 public:
  [[nodiscard]] bool fresh(const std::string& client, std::int64_t counter) const;
  void accept(const std::string& client, std::int64_t counter) { last_[client] = counter; }

 private:
  std::map<std::string, std::int64_t> last_;
};

}  // namespace plc::hmi

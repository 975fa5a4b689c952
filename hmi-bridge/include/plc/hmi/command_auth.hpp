// The shared-key authentication of the HMI bridge (hmi-bridge/README.md,
// "Authentication"), for the bridge and plcctl alike.
//
// Every tag is HMAC-SHA256 (libsodium crypto_auth_hmacsha256) over a
// domain-separated encoding of the context and the message:
//
//   "softplc-hmi" 0x00, protocol version, kind (command, reply, description),
//   len32 prefix, len32 cell, len32 channel, epoch (16 bytes),
//   len32 + the message's LCM encoding with its tag all zero
//
// (len32: a big-endian 32-bit length, then the bytes). The context is not
// sent (the epoch is, inside the message): each side puts in what it knows,
// so a command captured on one cell does not verify on another cell, under
// another prefix, on another channel, or as another kind of message.
//
// The boot epoch is 16 random bytes made when a Bridge is constructed: it
// lives exactly as long as the bridge's ReplayGuard, which remembers the
// counters seen in it. A new bridge (plcrun started again, the bridge's
// process restarted) has a new epoch, so a command signed for an earlier
// one - a capture replayed after a restart - is refused as stale without
// anything persisted; a rebuild of the runtime by goto/restart keeps the
// Bridge, its epoch and its counters. Clients learn the epoch from the cell
// description, which the bridge signs too.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>

#include "softplc_hmi/cell_description_t.hpp"
#include "softplc_hmi/command_t.hpp"
#include "softplc_hmi/reply_t.hpp"

namespace plc::hmi {

using Key = std::array<std::uint8_t, 32>;
using Epoch = std::array<std::uint8_t, 16>;

// The tag's protocol version (the domain's second field).
inline constexpr std::uint8_t kAuthVersion = 2;

// Reads a key file: 64 hex digits (32 bytes; `openssl rand -hex 32`),
// surrounding whitespace allowed. Refused, with the reason in `err`: a
// file that is not a regular file, is readable or writable by group or
// others (mode & 077), belongs to another user than this process's (or
// root), is larger than 4 kB, or does not hold exactly 64 hex digits.
std::optional<Key> load_key(const std::string& path, std::string& err);

// 16 random bytes (libsodium randombytes_buf: getrandom(2)).
Epoch new_epoch();
// A random request id, never 0 (plcctl: a reply to a request it did not
// send cannot be passed off as the answer to one it sends later).
std::int64_t random_request_id();

// What a tag binds besides the message itself.
struct TagContext {
  std::string prefix;   // the cell's hmi: prefix
  std::string cell;     // the cell's name
  std::string channel;  // the channel the message travels on
};

// The epoch a message carries, and whether it is all zero (unsigned).
Epoch epoch_of(const softplc_hmi::command_t& c);
Epoch epoch_of(const softplc_hmi::reply_t& r);
Epoch epoch_of(const softplc_hmi::cell_description_t& d);
void set_epoch(softplc_hmi::command_t& c, const Epoch& e);
void set_epoch(softplc_hmi::reply_t& r, const Epoch& e);
void set_epoch(softplc_hmi::cell_description_t& d, const Epoch& e);
std::string to_hex(const Epoch& e);

// Sets the message's tag for `key` in `ctx` (its epoch as it carries it).
void sign(softplc_hmi::command_t& c, const Key& key, const TagContext& ctx);
void sign(softplc_hmi::reply_t& r, const Key& key, const TagContext& ctx);
void sign(softplc_hmi::cell_description_t& d, const Key& key, const TagContext& ctx);
// Whether the message's tag is right for `key` in `ctx` (constant-time).
bool verify(const softplc_hmi::command_t& c, const Key& key, const TagContext& ctx);
bool verify(const softplc_hmi::reply_t& r, const Key& key, const TagContext& ctx);
bool verify(const softplc_hmi::cell_description_t& d, const Key& key, const TagContext& ctx);

// Within one epoch: the highest accepted counter per client, for at most
// kMaxClients clients. A command whose counter is not above its client's
// is a replay (or older than one already served). When the table is full,
// accepting a new client forgets the one with the lowest counter and
// raises a floor to that counter: a client the guard does not know must
// then be above the floor, so nothing the forgotten client ever sent
// becomes fresh again. Counters are therefore comparable across clients:
// plcctl takes the wall clock in microseconds.
class ReplayGuard {
 public:
  static constexpr std::size_t kMaxClients = 256;
  enum class Verdict { fresh, replayed, below_floor };
  [[nodiscard]] Verdict check(const std::string& client, std::int64_t counter) const;
  // After check() said fresh and the command's tag verified.
  void accept(const std::string& client, std::int64_t counter);
  [[nodiscard]] std::int64_t floor() const { return floor_; }
  [[nodiscard]] std::size_t clients() const { return last_.size(); }

 private:
  std::map<std::string, std::int64_t> last_;
  std::int64_t floor_ = std::numeric_limits<std::int64_t>::min();
};

}  // namespace plc::hmi

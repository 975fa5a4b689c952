#include "plc/hmi/command_auth.hpp"

#include <sodium.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <vector>

#include "plc/hmi/checked_file.hpp"

namespace plc::hmi {

namespace {

// Larger files are refused unread: a key file holds 64 hex digits.
constexpr std::size_t kMaxKeyFileBytes = 4096;

}  // namespace

std::optional<Key> load_key(const std::string& path, std::string& err) {
  if (sodium_init() < 0) {
    err = "libsodium cannot be initialised";
    return std::nullopt;
  }
  const FileRules rules{"key file", kMaxKeyFileBytes, ": a key file holds 64 hex digits", true,
                        "anyone who can read it can sign commands"};
  std::optional<std::string> text = read_checked_file(path, rules, err);
  if (!text) return std::nullopt;
  std::string hex;
  hex.reserve(text->size());  // no copies of the digits left in freed memory
  for (const char c : *text)
    if (!std::isspace(static_cast<unsigned char>(c))) hex += c;
  sodium_memzero(text->data(), text->size());
  Key k{};
  std::size_t len = 0;
  if (hex.size() != 64 ||
      sodium_hex2bin(k.data(), k.size(), hex.data(), hex.size(), nullptr, &len, nullptr) != 0 ||
      len != k.size()) {
    sodium_memzero(hex.data(), hex.size());
    err = "key file '" + path +
          "' must hold 64 hex digits (32 bytes; e.g. from `openssl rand -hex 32`)";
    return std::nullopt;
  }
  sodium_memzero(hex.data(), hex.size());
  return k;
}

Epoch new_epoch() {
  if (sodium_init() < 0) std::abort();  // no randomness: nothing may be signed
  Epoch e{};
  randombytes_buf(e.data(), e.size());
  return e;
}

std::int64_t random_request_id() {
  if (sodium_init() < 0) std::abort();
  for (;;) {
    std::uint64_t v = 0;
    randombytes_buf(&v, sizeof v);
    if (v != 0) return static_cast<std::int64_t>(v);
  }
}

namespace {

enum class Kind : std::uint8_t { command = 1, reply = 2, description = 3 };

template <class M>
Epoch epoch_from(const M& m) {
  Epoch e{};
  for (std::size_t i = 0; i < e.size(); ++i) e[i] = static_cast<std::uint8_t>(m.epoch[i]);
  return e;
}

template <class M>
void epoch_into(M& m, const Epoch& e) {
  for (std::size_t i = 0; i < e.size(); ++i) m.epoch[i] = static_cast<std::int8_t>(e[i]);
}

void update_len32(crypto_auth_hmacsha256_state& st, const void* data, std::size_t n) {
  const std::uint8_t len[4] = {std::uint8_t(n >> 24), std::uint8_t(n >> 16), std::uint8_t(n >> 8),
                               std::uint8_t(n)};
  crypto_auth_hmacsha256_update(&st, len, sizeof len);
  crypto_auth_hmacsha256_update(&st, static_cast<const std::uint8_t*>(data), n);
}

// The tag of m (its own tag taken as all zero) in ctx. The tag is the last
// field of each signed type (hmi-bridge/lcm/*.lcm; the shapes in
// checked_decode.hpp end in 32b): the encoding's last 32 bytes, zeroed in
// the buffer rather than in a copy of the message.
template <class M>
Key tag_of(const M& m, Kind kind, const Key& key, const TagContext& ctx) {
  const int n = m.getEncodedSize();
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(n));
  m.encode(buf.data(), 0, n);
  static_assert(sizeof m.tag == 32);
  std::fill(buf.end() - 32, buf.end(), std::uint8_t(0));
  const Epoch e = epoch_from(m);
  static constexpr char kDomain[] = "softplc-hmi";  // with its NUL
  const std::uint8_t head[2] = {kAuthVersion, static_cast<std::uint8_t>(kind)};
  crypto_auth_hmacsha256_state st;
  crypto_auth_hmacsha256_init(&st, key.data(), key.size());
  crypto_auth_hmacsha256_update(&st, reinterpret_cast<const std::uint8_t*>(kDomain),
                                sizeof kDomain);
  crypto_auth_hmacsha256_update(&st, head, sizeof head);
  update_len32(st, ctx.prefix.data(), ctx.prefix.size());
  update_len32(st, ctx.cell.data(), ctx.cell.size());
  update_len32(st, ctx.channel.data(), ctx.channel.size());
  crypto_auth_hmacsha256_update(&st, e.data(), e.size());
  update_len32(st, buf.data(), buf.size());
  Key t{};
  crypto_auth_hmacsha256_final(&st, t.data());
  return t;
}

template <class M>
void sign_as(M& m, Kind kind, const Key& key, const TagContext& ctx) {
  const Key t = tag_of(m, kind, key, ctx);
  for (std::size_t i = 0; i < t.size(); ++i) m.tag[i] = static_cast<std::int8_t>(t[i]);
}

template <class M>
bool verify_as(const M& m, Kind kind, const Key& key, const TagContext& ctx) {
  const Key t = tag_of(m, kind, key, ctx);
  std::uint8_t got[32];
  for (std::size_t i = 0; i < 32; ++i) got[i] = static_cast<std::uint8_t>(m.tag[i]);
  return sodium_memcmp(got, t.data(), t.size()) == 0;
}

}  // namespace

Epoch epoch_of(const softplc_hmi::command_t& c) { return epoch_from(c); }
Epoch epoch_of(const softplc_hmi::reply_t& r) { return epoch_from(r); }
Epoch epoch_of(const softplc_hmi::cell_description_t& d) { return epoch_from(d); }
void set_epoch(softplc_hmi::command_t& c, const Epoch& e) { epoch_into(c, e); }
void set_epoch(softplc_hmi::reply_t& r, const Epoch& e) { epoch_into(r, e); }
void set_epoch(softplc_hmi::cell_description_t& d, const Epoch& e) { epoch_into(d, e); }

std::string to_hex(const Epoch& e) {
  char b[2 * 16 + 1];
  sodium_bin2hex(b, sizeof b, e.data(), e.size());
  return b;
}

void sign(softplc_hmi::command_t& c, const Key& key, const TagContext& ctx) {
  sign_as(c, Kind::command, key, ctx);
}
void sign(softplc_hmi::reply_t& r, const Key& key, const TagContext& ctx) {
  sign_as(r, Kind::reply, key, ctx);
}
void sign(softplc_hmi::cell_description_t& d, const Key& key, const TagContext& ctx) {
  sign_as(d, Kind::description, key, ctx);
}
bool verify(const softplc_hmi::command_t& c, const Key& key, const TagContext& ctx) {
  return verify_as(c, Kind::command, key, ctx);
}
bool verify(const softplc_hmi::reply_t& r, const Key& key, const TagContext& ctx) {
  return verify_as(r, Kind::reply, key, ctx);
}
bool verify(const softplc_hmi::cell_description_t& d, const Key& key, const TagContext& ctx) {
  return verify_as(d, Kind::description, key, ctx);
}

ReplayGuard::Verdict ReplayGuard::check(const std::string& client, std::int64_t counter) const {
  auto it = last_.find(client);
  if (it != last_.end()) return counter > it->second ? Verdict::fresh : Verdict::replayed;
  return counter > floor_ ? Verdict::fresh : Verdict::below_floor;
}

void ReplayGuard::accept(const std::string& client, std::int64_t counter) {
  auto it = last_.find(client);
  if (it != last_.end()) {
    it->second = counter;
    return;
  }
  if (last_.size() >= kMaxClients) {
    auto oldest = std::min_element(last_.begin(), last_.end(), [](const auto& a, const auto& b) {
      return a.second < b.second;
    });
    floor_ = std::max(floor_, oldest->second);
    last_.erase(oldest);
  }
  last_.emplace(client, counter);
}

}  // namespace plc::hmi

#include "plc/hmi/command_auth.hpp"

#include <sodium.h>

#include <cctype>
#include <fstream>
#include <sstream>
#include <vector>

namespace plc::hmi {

std::optional<Key> load_key(const std::string& path, std::string& err) {
  if (sodium_init() < 0) {
    err = "libsodium cannot be initialised";
    return std::nullopt;
  }
  std::ifstream f(path);
  if (!f) {
    err = "cannot read key file '" + path + "'";
    return std::nullopt;
  }
  std::stringstream ss;
  ss << f.rdbuf();
  std::string hex;
  for (char ch : ss.str())
    if (!std::isspace(static_cast<unsigned char>(ch))) hex += ch;
  Key k{};
  std::size_t len = 0;
  if (hex.size() != 64 ||
      sodium_hex2bin(k.data(), k.size(), hex.data(), hex.size(), nullptr, &len, nullptr) != 0 ||
      len != k.size()) {
    err = "key file '" + path +
          "' must hold 64 hex digits (32 bytes; e.g. from `openssl rand -hex 32`)";
    return std::nullopt;
  }
  return k;
}

namespace {
Key tag_of(softplc_hmi::command_t c, const Key& key) {
  std::fill(std::begin(c.tag), std::end(c.tag), std::int8_t(0));
  const int n = c.getEncodedSize();
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(n));
  c.encode(buf.data(), 0, n);
  Key t{};
  crypto_auth_hmacsha256(t.data(), buf.data(), buf.size(), key.data());
  return t;
}
}  // namespace

void sign(softplc_hmi::command_t& c, const Key& key) {
  const Key t = tag_of(c, key);
  for (std::size_t i = 0; i < t.size(); ++i) c.tag[i] = static_cast<std::int8_t>(t[i]);
}

bool verify(const softplc_hmi::command_t& c, const Key& key) {
  const Key t = tag_of(c, key);
  std::uint8_t got[32];
  for (std::size_t i = 0; i < 32; ++i) got[i] = static_cast<std::uint8_t>(c.tag[i]);
  return sodium_memcmp(got, t.data(), t.size()) == 0;
}

bool ReplayGuard::fresh(const std::string& client, std::int64_t counter) const {
  auto it = last_.find(client);
  return it == last_.end() || counter > it->second;
}

}  // namespace plc::hmi

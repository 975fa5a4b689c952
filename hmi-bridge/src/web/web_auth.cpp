#include "plc/hmi/web/web_auth.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/rand.h>

#include <algorithm>
#include <stdexcept>

namespace plc::hmi::web {

namespace {

std::string to_hex(const unsigned char* p, std::size_t n) {
  static const char* d = "0123456789abcdef";
  std::string s(2 * n, '0');
  for (std::size_t i = 0; i < n; ++i) {
    s[2 * i] = d[p[i] >> 4];
    s[2 * i + 1] = d[p[i] & 15];
  }
  return s;
}

std::optional<std::vector<unsigned char>> from_hex(std::string_view s) {
  if (s.size() % 2) return std::nullopt;
  auto nib = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  std::vector<unsigned char> out(s.size() / 2);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const int h = nib(s[2 * i]), l = nib(s[2 * i + 1]);
    if (h < 0 || l < 0) return std::nullopt;
    out[i] = static_cast<unsigned char>(h * 16 + l);
  }
  return out;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  for (std::size_t from = 0;;) {
    const auto d = s.find(sep, from);
    parts.push_back(s.substr(from, d == std::string_view::npos ? d : d - from));
    if (d == std::string_view::npos) break;
    from = d + 1;
  }
  return parts;
}

bool pbkdf2(std::string_view password, const std::vector<unsigned char>& salt, int iterations,
            unsigned char* out, std::size_t n) {
  return PKCS5_PBKDF2_HMAC(password.data(), int(password.size()), salt.data(), int(salt.size()),
                           iterations, EVP_sha256(), int(n), out) == 1;
}

}  // namespace

bool verify_key_text(std::string_view text, const std::array<unsigned char, 32>& key) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.remove_suffix(1);
  const auto bytes = from_hex(text);
  return bytes && bytes->size() == key.size() &&
         CRYPTO_memcmp(bytes->data(), key.data(), key.size()) == 0;
}

std::string random_token() {
  unsigned char b[32];
  if (RAND_bytes(b, sizeof b) != 1) throw std::runtime_error("RAND_bytes failed");
  return to_hex(b, sizeof b);
}

std::string hash_password(std::string_view password, int iterations) {
  std::vector<unsigned char> salt(16);
  if (RAND_bytes(salt.data(), int(salt.size())) != 1) throw std::runtime_error("RAND_bytes failed");
  unsigned char h[32];
  if (!pbkdf2(password, salt, iterations, h, sizeof h))
    throw std::runtime_error("PKCS5_PBKDF2_HMAC failed");
  return "pbkdf2-sha256$" + std::to_string(iterations) + "$" + to_hex(salt.data(), salt.size()) +
         "$" + to_hex(h, sizeof h);
}

bool verify_password(std::string_view password, std::string_view hash) {
  const auto parts = split(hash, '$');
  if (parts.size() != 4 || parts[0] != "pbkdf2-sha256") return false;
  if (parts[1].empty() || parts[1].size() > 8 ||
      parts[1].find_first_not_of("0123456789") != std::string_view::npos)
    return false;
  const int iterations = std::stoi(std::string(parts[1]));
  const auto salt = from_hex(parts[2]);
  const auto want = from_hex(parts[3]);
  // The same bounds as the config's check (cell_config.cpp).
  if (iterations < 1000 || iterations > 10'000'000 || !salt || !want || salt->size() < 8 ||
      want->size() < 16 || want->size() > 32)
    return false;
  unsigned char got[32];
  if (!pbkdf2(password, *salt, iterations, got, want->size())) return false;
  return CRYPTO_memcmp(got, want->data(), want->size()) == 0;
}

std::pair<std::string, std::string> Sessions::open(std::chrono::steady_clock::time_point now) {
  for (auto it = by_token_.begin(); it != by_token_.end();)
    it = now - it->second.last_used > idle_ ? by_token_.erase(it) : std::next(it);
  if (by_token_.size() >= kMax) {
    auto oldest = std::min_element(by_token_.begin(), by_token_.end(), [](auto& a, auto& b) {
      return a.second.last_used < b.second.last_used;
    });
    by_token_.erase(oldest);
  }
  std::string token = random_token();
  Session s{random_token(), now};
  by_token_[token] = s;
  return {token, s.csrf};
}

const Session* Sessions::find(std::string_view token, std::chrono::steady_clock::time_point now) {
  if (token.size() != 64) return nullptr;
  const auto it = by_token_.find(token);
  if (it == by_token_.end()) return nullptr;
  if (now - it->second.last_used > idle_) {
    by_token_.erase(it);
    return nullptr;
  }
  it->second.last_used = now;
  return &it->second;
}

void Sessions::close(std::string_view token) {
  if (const auto it = by_token_.find(token); it != by_token_.end()) by_token_.erase(it);
}

std::string cookie_value(std::string_view header, std::string_view name) {
  for (std::string_view part : split(header, ';')) {
    while (!part.empty() && part.front() == ' ') part.remove_prefix(1);
    if (part.size() > name.size() && part.substr(0, name.size()) == name &&
        part[name.size()] == '=')
      return std::string(part.substr(name.size() + 1));
  }
  return "";
}

std::vector<std::string> allowed_hosts(const std::string& address, int port) {
  const std::string p = ":" + std::to_string(port);
  std::vector<std::string> out;
  const bool v6 = address.find(':') != std::string::npos;
  out.push_back((v6 ? "[" + address + "]" : address) + p);
  if (address.rfind("127.", 0) == 0 || address == "::1") out.push_back("localhost" + p);
  return out;
}

bool same_origin(std::string_view origin, std::string_view host, bool tls) {
  const std::string want = std::string(tls ? "https://" : "http://") + std::string(host);
  return origin == want;
}

}  // namespace plc::hmi::web

#include "plc/hmi/lcm_url.hpp"

#include <arpa/inet.h>

#include <charconv>
#include <string_view>

namespace plc::hmi {

namespace {

// A decimal number in [lo, hi], digits only (liblcm's strtol also takes
// "0x10", "-1" and "12abc").
std::optional<long> number(std::string_view s, long lo, long hi) {
  long v = 0;
  if (s.empty() || s.find_first_not_of("0123456789") != std::string_view::npos) return std::nullopt;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || v < lo || v > hi) return std::nullopt;
  return v;
}

constexpr const char* kForms = " (udpm://ADDR:PORT?ttl=N&recv_buf_size=BYTES or memq://)";

}  // namespace

std::optional<LcmUrl> parse_lcm_url(const std::string& url, std::string& error) {
  const std::string_view u(url);
  const auto sep = u.find("://");
  if (sep == std::string_view::npos) {
    error = "'" + url + "' is not an LCM url" + kForms;
    return std::nullopt;
  }
  const std::string_view provider = u.substr(0, sep), rest = u.substr(sep + 3);
  LcmUrl r;
  if (provider == "memq") {
    if (!rest.empty()) {
      error = "'" + url + "': memq:// takes no address and no options";
      return std::nullopt;
    }
    r.kind = LcmUrl::Kind::Memq;
    return r;
  }
  if (provider != "udpm") {
    error = "'" + url + "': provider '" + std::string(provider) + "' is not offered" + kForms +
            (provider == "tcpq" ? "; tcpq:// would receive through liblcm's own parser" : "");
    return std::nullopt;
  }
  const auto q = rest.find('?');
  const std::string_view network = rest.substr(0, q);
  if (!network.empty()) {  // empty: liblcm's default group and port
    const auto colon = network.find(':');
    if (colon == std::string_view::npos) {
      error = "'" + url + "': '" + std::string(network) + "' has no port (udpm://ADDR:PORT)";
      return std::nullopt;
    }
    const std::string addr(network.substr(0, colon));
    in_addr a{};
    if (::inet_pton(AF_INET, addr.c_str(), &a) != 1) {
      error = "'" + url + "': '" + addr + "' is not an IPv4 address";
      return std::nullopt;
    }
    r.group = ntohl(a.s_addr);
    if ((r.group >> 28) != 0xE) {
      error =
          "'" + url + "': " + addr + " is not a multicast address (224.0.0.0 to 239.255.255.255)";
      return std::nullopt;
    }
    const auto port = number(network.substr(colon + 1), 1, 65535);
    if (!port) {
      error = "'" + url + "': port '" + std::string(network.substr(colon + 1)) +
              "' is not a number from 1 to 65535";
      return std::nullopt;
    }
    r.port = std::uint16_t(*port);
  }
  bool seen_ttl = false, seen_buf = false;
  std::string_view options = q == std::string_view::npos ? std::string_view() : rest.substr(q + 1);
  // Bounded: each round consumes one option and its '&'.
  while (q != std::string_view::npos) {
    const auto amp = options.find('&');
    const std::string_view opt = options.substr(0, amp);
    const auto eq = opt.find('=');
    const std::string_view key = opt.substr(0, eq);
    const std::string_view value = eq == std::string_view::npos ? "" : opt.substr(eq + 1);
    if (key == "ttl" && !seen_ttl) {
      const auto v = number(value, 0, 255);
      if (!v) {
        error = "'" + url + "': ttl '" + std::string(value) + "' is not a number from 0 to 255";
        return std::nullopt;
      }
      r.ttl = int(*v);
      seen_ttl = true;
    } else if (key == "recv_buf_size" && !seen_buf) {
      const auto v = number(value, 1, 1 << 28);
      if (!v) {
        error = "'" + url + "': recv_buf_size '" + std::string(value) +
                "' is not a number of bytes from 1 to 268435456";
        return std::nullopt;
      }
      r.recv_buf_size = int(*v);
      seen_buf = true;
    } else {
      error = "'" + url + "': option '" + std::string(opt) +
              ((key == "ttl" || key == "recv_buf_size") ? "' is given twice"
                                                        : "' is not known (udpm takes ttl and "
                                                          "recv_buf_size)");
      return std::nullopt;
    }
    if (amp == std::string_view::npos) break;
    options = options.substr(amp + 1);
  }
  return r;
}

}  // namespace plc::hmi

// Fuzz target: what the web HMI's server (plchmi, issue 27) reads from a
// browser, with the server's own bounds. The first byte picks the part:
//  0 an HTTP request into Boost.Beast's request parser with the server's
//    header (8 KiB) and body (4 KiB) limits, then its Cookie header into
//    cookie_value() and its body into parse_command_body(). Properties: the
//    parser never holds a header or body over its limit; a parsed command
//    has a known verb, at most 8 arguments of at most 512 bytes, none with
//    a control character;
//  1 the rest as a command body; the same properties;
//  2 the rest as a login password against the HMI key (verify_key_text):
//    true only for the key's own hex digits.
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
// Boost 1.74's asio/awaitable.hpp uses std::exchange without <utility>.
#include <utility>
// clang-format off: <utility> first
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
// clang-format on

#include "plc/hmi/web/command_body.hpp"
#include "plc/hmi/web/web_auth.hpp"

namespace {

void check_command(std::string_view body) {
  plc::hmi::web::CommandBody c;
  std::string err;
  if (!plc::hmi::web::parse_command_body(body, c, err)) {
    if (err.empty()) __builtin_trap();
    return;
  }
  static const std::array<std::string_view, 8> verbs = {"read",  "write", "force",    "unforce",
                                                        "pause", "step",  "continue", "ack"};
  if (std::find(verbs.begin(), verbs.end(), c.verb) == verbs.end()) __builtin_trap();
  if (c.args.size() > plc::hmi::web::kMaxCommandArgs) __builtin_trap();
  for (const auto& a : c.args) {
    if (a.size() > plc::hmi::web::kMaxCommandLine) __builtin_trap();
    for (char ch : a)
      if (static_cast<unsigned char>(ch) < 0x20) __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view rest(reinterpret_cast<const char*>(data + 1), size - 1);
  switch (data[0] % 3) {
    case 0: {
      namespace http = boost::beast::http;
      http::request_parser<http::string_body> p;
      p.header_limit(8192);
      p.body_limit(plc::hmi::web::kMaxCommandBody);
      p.eager(true);
      boost::beast::error_code ec;
      std::size_t used = 0;
      for (int i = 0; i < 64 && used < rest.size() && !p.is_done(); ++i) {
        const std::size_t n =
            p.put(boost::asio::buffer(rest.data() + used, rest.size() - used), ec);
        if (ec == http::error::need_more) break;
        if (ec) return 0;
        if (n == 0) break;
        used += n;
      }
      if (!p.is_header_done()) return 0;
      const auto& req = p.get();
      if (req.body().size() > plc::hmi::web::kMaxCommandBody) __builtin_trap();
      const auto cookie = req[http::field::cookie];
      const std::string v = plc::hmi::web::cookie_value(
          std::string_view(cookie.data(), cookie.size()), "plc_session");
      if (v.size() > cookie.size()) __builtin_trap();
      check_command(req.body());
      break;
    }
    case 1:
      check_command(rest);
      break;
    case 2: {
      std::array<unsigned char, 32> key{};
      for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<unsigned char>(i * 37);
      if (plc::hmi::web::verify_key_text(rest, key)) {
        std::string hex;
        static const char* d = "0123456789abcdef";
        for (auto c : key) {
          hex += d[c >> 4];
          hex += d[c & 15];
        }
        std::string got(rest.substr(0, 64));
        std::transform(got.begin(), got.end(), got.begin(),
                       [](char c) { return char(c >= 'A' && c <= 'F' ? c - 'A' + 'a' : c); });
        if (got != hex) __builtin_trap();
      }
      break;
    }
  }
  return 0;
}

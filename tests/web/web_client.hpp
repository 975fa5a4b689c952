// A script client of the web HMI for the tests: HTTP requests and a
// WebSocket over loopback (Boost.Beast, synchronous, every read bounded
// by a socket timeout), and a raw socket for clients that misbehave.
#pragma once

#include <sys/socket.h>
#include <sys/time.h>

// Boost 1.74's asio/awaitable.hpp uses std::exchange without <utility>.
#include <utility>
// clang-format off: <utility> first
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
// clang-format on
#include <map>
#include <string>

namespace webtest {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

struct Response {
  int status = 0;
  std::string body;
  std::string set_cookie;
  std::string retry_after;
};

inline void set_timeout(int fd, int ms) {
  timeval tv{ms / 1000, (ms % 1000) * 1000};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
}

// A request from loopback address `from` ("127.0.0.2": any of 127/8 is this
// host; "" lets the kernel choose), as another client would send it.
inline Response request_from(const std::string& from, int port, http::verb method,
                             const std::string& target, std::map<std::string, std::string> headers,
                             const std::string& body = "") {
  asio::io_context ioc;
  tcp::socket s(ioc);
  if (!from.empty()) {
    s.open(tcp::v4());
    s.bind({asio::ip::make_address(from), 0});
  }
  s.connect({asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
  set_timeout(s.native_handle(), 10000);
  http::request<http::string_body> req{method, target, 11};
  req.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  for (const auto& [k, v] : headers) req.set(k, v);
  req.body() = body;
  req.prepare_payload();
  http::write(s, req);
  beast::flat_buffer buf;
  http::response<http::string_body> res;
  beast::error_code ec;
  http::read(s, buf, res, ec);
  Response r;
  if (ec) return r;
  r.status = res.result_int();
  r.body = res.body();
  r.set_cookie = std::string(res[http::field::set_cookie]);
  r.retry_after = std::string(res[http::field::retry_after]);
  return r;
}

inline Response request(int port, http::verb method, const std::string& target,
                        std::map<std::string, std::string> headers, const std::string& body = "") {
  return request_from("", port, method, target, std::move(headers), body);
}

}  // namespace webtest

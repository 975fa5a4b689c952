// The web server's state, on its own thread (the io_context's): private to
// hmi-bridge/src/web/. The bridge's thread reaches it only through post().
#pragma once

// Boost 1.74's asio/awaitable.hpp uses std::exchange without <utility>.
#include <utility>
// clang-format off: <utility> first
#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
// clang-format on
#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "plc/hmi/web/login_limiter.hpp"
#include "plc/hmi/web/web_auth.hpp"
#include "plc/hmi/web/web_server.hpp"

namespace plc::hmi::web {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using Message = std::shared_ptr<const std::string>;
// A connection is plain TCP or, with hmi: web: tls:, TLS over it: one
// server serves one of them only (no plain request reaches a TLS server).
using PlainStream = beast::tcp_stream;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;
using Stream = std::variant<PlainStream, TlsStream>;
using WsStream = std::variant<websocket::stream<PlainStream>, websocket::stream<TlsStream>>;

inline std::string_view sv(beast::string_view s) { return {s.data(), s.size()}; }

inline constexpr std::size_t kMaxHeader = 8192;
inline constexpr std::size_t kMaxBacklog = 256;
inline constexpr std::size_t kMaxWsIn = 1024;
inline constexpr std::size_t kAlarmHistory = 200;
inline constexpr auto kReplyTimeout = std::chrono::seconds(5);
inline constexpr auto kTlsHandshakeTimeout = std::chrono::seconds(10);

class HttpSession;
class WsSession;

struct WebServer::Impl {
  Impl(Bridge& b, WebOptions o);
  // Destroys what the io_context still holds (handlers keep sessions,
  // sessions point here) while everything they touch is alive.
  ~Impl();

  Bridge& bridge;
  WebOptions opt;
  std::optional<asio::ssl::context> tls;  // hmi: web: tls: (outlives the sessions, ~Impl)
  std::unique_ptr<asio::io_context> io = std::make_unique<asio::io_context>(1);
  std::optional<tcp::acceptor> acceptor;
  std::thread thread;
  int port = 0;                    // bound
  std::vector<std::string> hosts;  // allowed Host headers
  std::string login_name;          // "none", "key", "password"

  [[nodiscard]] std::chrono::steady_clock::time_point now() const {
    return opt.clock ? opt.clock() : std::chrono::steady_clock::now();
  }

  // Only on the io thread:
  Sessions sessions;
  LoginLimiter login_limiter;
  std::set<std::shared_ptr<WsSession>> pages;
  std::set<HttpSession*> connections;                            // open, not upgraded
  std::map<std::int64_t, std::shared_ptr<HttpSession>> waiting;  // request id -> the POST
  std::int64_t next_request = 1;
  Message desc;
  std::int64_t desc_layout = 0;
  std::string desc_cell;
  std::map<int, std::pair<std::string, double>> latest;  // var -> text, number
  std::map<std::string, std::int64_t> latest_scan;       // task -> scan
  Message stats, diag;
  // The last alarm events, for a page that opens now; acknowledged from any
  // page (verb "ack", kept by this server: the cell knows nothing of it).
  struct Alarm {
    std::int64_t id;
    softplc_hmi::alarm_t alarm;
    bool acked = false;
    Message json;
  };
  std::deque<Alarm> alarms;
  std::int64_t next_alarm = 1;
  // "ack ID" or "ack all": the reply's JSON.
  std::string acknowledge(const std::string& which);

  std::atomic<std::size_t> backlog{0};  // posted by the bridge's thread, not run yet
  mutable std::mutex counters_mu;
  WebCounters counters;
  template <class F>
  void count(F f) {
    std::lock_guard<std::mutex> lock(counters_mu);
    f(counters);
  }
  [[nodiscard]] std::string counters_json() const;

  void accept();
  void shut_down();  // on the io thread: closes everything, so that run() returns
  void broadcast(const Message& m);
  void open_page(const std::shared_ptr<WsSession>& page);
  // Hands the bridge's work to the io thread; `droppable`: values, which
  // the next full snapshot repeats.
  template <class F>
  void post(F f, bool droppable) {
    if (droppable && backlog.load(std::memory_order_relaxed) >= kMaxBacklog) {
      count([](WebCounters& c) { ++c.backlog_dropped; });
      return;
    }
    backlog.fetch_add(1, std::memory_order_relaxed);
    asio::post(*io, [this, f = std::move(f)]() mutable {
      backlog.fetch_sub(1, std::memory_order_relaxed);
      f();
    });
  }
};

// One HTTP connection: requests one after another (keep-alive); a
// WebSocket upgrade hands the stream to a WsSession.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(WebServer::Impl* server, tcp::socket socket);
  ~HttpSession();
  void run();  // the TLS handshake first, with tls
  void close();
  // The bridge's answer to this connection's command (or the timeout's).
  void answer(http::status status, std::string json);

 private:
  void read();
  void on_read(beast::error_code ec);
  void handle();
  void handle_api(const std::string& target);
  void login(std::chrono::steady_clock::time_point now);
  void send(http::response<http::string_body> res);
  void send_json(http::status status, std::string json);
  void refuse(http::status status, const std::string& why);
  // The session of the request's cookie, refreshed (nullptr: none).
  const Session* session();
  bool check_host();
  bool check_origin();
  beast::tcp_stream& tcp();
  // "; Secure" with TLS: the browser sends the cookie over HTTPS only.
  std::string cookie(const std::string& token) const;

  WebServer::Impl* server_;
  Stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  http::request<http::string_body> req_;
  asio::steady_timer reply_timer_;
  std::int64_t waiting_for_ = 0;
  std::string client_;  // the peer's address_key(), for the login limit
};

// One page's WebSocket: everything the bridge publishes, in order, through
// a bounded queue.
class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(WebServer::Impl* server, Stream&& stream);
  void accept(http::request<http::string_body> req);
  void send(const Message& m);
  void close();

 private:
  void read();
  void write();
  beast::tcp_stream& tcp();

  WebServer::Impl* server_;
  WsStream ws_;
  beast::flat_buffer in_;
  std::deque<Message> queue_;
  std::size_t queued_bytes_ = 0;
  bool writing_ = false;
  bool open_ = false;
  bool closed_ = false;
};

// The page's files, built into plchmi from hmi-bridge/web/ (web_assets.cmake).
struct Asset {
  const char* path;  // "/index.html"
  const char* type;  // Content-Type
  const unsigned char* data;
  std::size_t size;
};
const Asset* find_asset(const std::string& path);

}  // namespace plc::hmi::web

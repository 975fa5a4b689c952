// The browser HMI's server inside plchmi (hmi-bridge/README.md "Web HMI";
// never in plcrun): HTTP and one WebSocket per page on Boost.Beast, on its
// own thread. It sees what the bridge publishes through the bridge's tap,
// and sends commands through Bridge::submit(), so a write from the page
// takes the same path as one from plcctl: the writable/forceable patterns
// and stop_commands in the bridge, plcrun's own check of the record.
//
// Bounded everywhere: HTTP headers 8 KiB, bodies 4 KiB, WebSocket messages
// from a page 1 KiB, 64 connections, per page a send queue of
// `max_queue_messages` / `max_queue_bytes` (a page that does not keep up is
// disconnected and counted; it reconnects and gets a fresh picture), and
// what the bridge hands over waits in a backlog of 256 (beyond that values
// are dropped and counted): the bridge's thread never waits for a browser,
// and a scan never waits for the bridge.
//
// Logins are limited per client address (login_limiter.hpp: 5 failures
// within a minute, then 429 for a minute).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "plc/hmi/bridge.hpp"
#include "plc/hmi/command_auth.hpp"
#include "plc/hmi/ipc/layout.hpp"

namespace plc::hmi::web {

struct WebOptions {
  std::string address = "127.0.0.1";
  int port = 8080;  // 0: any free port (tests; port() says which)
  bool read_only = false;
  ipc::WebLogin login = ipc::WebLogin::None;
  std::string password_hash;  // login == Hash
  std::optional<Key> key;     // login == Key: its 64 hex digits are the password
  // hmi: web: tls: PEM texts (plcrun read and checked them); both set:
  // HTTPS and WSS only, TLS 1.2 at least. Throws "hmi: web: tls: ..." when
  // OpenSSL does not take them.
  std::string tls_cert_pem, tls_key_pem;
  std::size_t max_queue_messages = 64;
  std::size_t max_queue_bytes = 4u << 20;
  std::size_t max_connections = 64;
  // The time of sessions and of the login limit (login_limiter.hpp);
  // empty: std::chrono::steady_clock. Tests give one they advance.
  std::function<std::chrono::steady_clock::time_point()> clock;
};

// The options plcrun handed over in the state region (plchmi's main).
WebOptions web_options(const ipc::Settings& settings);

// What the server did, for the page (stats), the tests and the benchmark.
struct WebCounters {
  std::uint64_t connections = 0;          // TCP connections accepted
  std::uint64_t tls_failed = 0;           // TLS handshakes that failed or timed out
  std::uint64_t refused_connections = 0;  // beyond max_connections
  std::uint64_t pages = 0;                // WebSockets open now
  std::uint64_t sent = 0;                 // WebSocket messages written
  std::uint64_t dropped = 0;              // messages not sent: a page's queue was full
  std::uint64_t slow_pages = 0;           // pages disconnected for it
  std::uint64_t backlog_dropped = 0;      // values the web thread had no time for
  std::uint64_t logins = 0, login_failed = 0;
  std::uint64_t login_locked = 0;  // logins refused unchecked: too many failures (HTTP 429)
  std::uint64_t no_session = 0;    // requests for data or commands without a session
  std::uint64_t bad_origin = 0;    // a write or a WebSocket from another origin, or without one
  std::uint64_t bad_host = 0;      // a Host header that is not this server (DNS rebinding)
  std::uint64_t bad_csrf = 0;      // a write without the session's X-CSRF-Token
  std::uint64_t too_large = 0;     // headers, body or WebSocket message over the bound
  std::uint64_t commands = 0;      // handed to the bridge
  std::uint64_t read_only_refused = 0;
};

class WebServer final : public BridgeTap {
 public:
  // Binds (throws std::runtime_error "hmi: web: cannot listen on ...").
  WebServer(Bridge& bridge, WebOptions options);
  ~WebServer() override;
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  void start();  // the server's thread
  void stop();
  [[nodiscard]] int port() const;
  [[nodiscard]] WebCounters counters() const;

  void on_description(const softplc_hmi::cell_description_t&) override;
  void on_values(const softplc_hmi::values_t&, const softplc_hmi::trace_sample_t&) override;
  void on_stats(const softplc_hmi::stats_t&) override;
  void on_diagnostics(const softplc_hmi::diagnostics_t&) override;
  void on_alarm(const softplc_hmi::alarm_t&) override;
  void on_reply(const softplc_hmi::reply_t&) override;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace plc::hmi::web

// One HTTP connection of the browser HMI: the page's files, the login, the
// commands (hmi-bridge/README.md "Web HMI", "Security").
#include <boost/beast/version.hpp>

#include "plc/hmi/web/command_body.hpp"
#include "plc/hmi/web/json.hpp"
#include "web_impl.hpp"

namespace plc::hmi::web {

namespace {

constexpr const char* kCookie = "plc_session";
constexpr auto kReadTimeout = std::chrono::seconds(30);
constexpr std::size_t kMaxPassword = 256;

std::string json_refusal(const std::string& why) {
  std::string out = R"({"ok":false,"refusal":)";
  append_string(out, why);
  out += '}';
  return out;
}

Stream make_stream(WebServer::Impl* server, tcp::socket socket) {
  if (server->tls) return Stream(std::in_place_type<TlsStream>, std::move(socket), *server->tls);
  return Stream(std::in_place_type<PlainStream>, std::move(socket));
}

}  // namespace

HttpSession::HttpSession(WebServer::Impl* server, tcp::socket socket)
    : server_(server), stream_(make_stream(server, std::move(socket))), reply_timer_(*server->io) {
  server_->connections.insert(this);
  // What the kernel holds for a page that does not read is bounded too: its
  // queue (WsSession) fills after this much and it is dropped.
  beast::error_code ignored;
  tcp().socket().set_option(asio::socket_base::send_buffer_size(64 * 1024), ignored);
  // A message goes out whole at once: without this Nagle's algorithm holds
  // its last segment for the page's delayed ACK (40 ms).
  tcp().socket().set_option(tcp::no_delay(true), ignored);
  // A peer whose address cannot be read (gone already) shares one key.
  const auto peer = tcp().socket().remote_endpoint(ignored);
  client_ = ignored ? "unknown" : address_key(peer.address().to_string());
}

beast::tcp_stream& HttpSession::tcp() {
  return std::visit([](auto& s) -> beast::tcp_stream& { return beast::get_lowest_layer(s); },
                    stream_);
}

std::string HttpSession::cookie(const std::string& token) const {
  return std::string(kCookie) + "=" + token + "; Path=/; HttpOnly; SameSite=Strict" +
         (server_->tls ? "; Secure" : "");
}

void HttpSession::run() {
  auto* tls = std::get_if<TlsStream>(&stream_);
  if (!tls) return read();
  // Bounded as a request: a client that never finishes its hello goes.
  tcp().expires_after(kTlsHandshakeTimeout);
  tls->async_handshake(asio::ssl::stream_base::server,
                       [self = shared_from_this()](beast::error_code ec) {
                         if (!ec) return self->read();
                         // Plain HTTP, an old protocol, a timeout: no answer.
                         self->server_->count([](WebCounters& c) { ++c.tls_failed; });
                         self->close();
                       });
}

HttpSession::~HttpSession() { server_->connections.erase(this); }

void HttpSession::close() {
  beast::error_code ignored;
  reply_timer_.cancel();
  // The socket, without TLS close_notify: a peer that does not read would
  // hold it (the browser takes a closed connection as the end).
  tcp().socket().shutdown(tcp::socket::shutdown_both, ignored);
  tcp().close();
}

void HttpSession::read() {
  parser_.emplace();
  parser_->header_limit(kMaxHeader);
  parser_->body_limit(kMaxCommandBody);
  req_ = {};
  tcp().expires_after(kReadTimeout);
  std::visit(
      [this](auto& s) {
        http::async_read(
            s, buffer_, *parser_,
            [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
      },
      stream_);
}

void HttpSession::on_read(beast::error_code ec) {
  if (ec == http::error::header_limit || ec == http::error::body_limit ||
      ec == http::error::buffer_overflow) {
    server_->count([](WebCounters& c) { ++c.too_large; });
    req_ = {};
    req_.version(11);
    req_.keep_alive(false);
    refuse(http::status::payload_too_large, "request too large");
    return;
  }
  if (ec) return close();  // closed, timed out or not HTTP: nothing to answer
  req_ = parser_->release();
  handle();
}

void HttpSession::send(http::response<http::string_body> res) {
  res.set(http::field::server, "plchmi");
  res.set(http::field::cache_control, "no-store");
  res.set("X-Content-Type-Options", "nosniff");
  res.set("X-Frame-Options", "DENY");
  res.set("Referrer-Policy", "no-referrer");
  res.set("Content-Security-Policy",
          "default-src 'self'; connect-src 'self'; img-src 'self' data: blob:; "
          "style-src 'self'; script-src 'self'; frame-ancestors 'none'; form-action 'self'");
  res.keep_alive(req_.keep_alive());
  res.prepare_payload();
  auto sp = std::make_shared<http::response<http::string_body>>(std::move(res));
  tcp().expires_after(kReadTimeout);
  std::visit(
      [this, &sp](auto& s) {
        http::async_write(s, *sp,
                          [self = shared_from_this(), sp](beast::error_code ec, std::size_t) {
                            if (ec || !sp->keep_alive()) return self->close();
                            self->read();
                          });
      },
      stream_);
}

void HttpSession::send_json(http::status status, std::string json) {
  http::response<http::string_body> res{status, req_.version()};
  res.set(http::field::content_type, "application/json");
  res.body() = std::move(json);
  send(std::move(res));
}

void HttpSession::refuse(http::status status, const std::string& why) {
  send_json(status, json_refusal(why));
}

void HttpSession::answer(http::status status, std::string json) {
  reply_timer_.cancel();
  waiting_for_ = 0;
  send_json(status, std::move(json));
}

const Session* HttpSession::session() {
  const auto it = req_.find(http::field::cookie);
  if (it == req_.end()) return nullptr;
  const std::string token = cookie_value(std::string(it->value()), kCookie);
  return server_->sessions.find(token, server_->now());
}

bool HttpSession::check_host() {
  const std::string host(req_[http::field::host]);
  for (const auto& h : server_->hosts)
    if (h == host) return true;
  server_->count([](WebCounters& c) { ++c.bad_host; });
  refuse(http::status::misdirected_request, "this server is not '" + host + "'");
  return false;
}

bool HttpSession::check_origin() {
  if (same_origin(sv(req_[http::field::origin]), sv(req_[http::field::host]),
                  server_->tls.has_value()))
    return true;
  server_->count([](WebCounters& c) { ++c.bad_origin; });
  refuse(http::status::forbidden, "another origin (or none): refused");
  return false;
}

void HttpSession::handle() {
  if (!check_host()) return;
  std::string target(req_.target());
  if (const auto q = target.find('?'); q != std::string::npos) target.resize(q);
  if (target.rfind("/api/", 0) == 0) return handle_api(target);
  if (req_.method() != http::verb::get && req_.method() != http::verb::head)
    return refuse(http::status::method_not_allowed, "GET only");
  const Asset* a = find_asset(target == "/" ? "/index.html" : target);
  if (!a) return refuse(http::status::not_found, "no such file");
  http::response<http::string_body> res{http::status::ok, req_.version()};
  res.set(http::field::content_type, a->type);
  if (req_.method() == http::verb::get)
    res.body().assign(reinterpret_cast<const char*>(a->data), a->size);
  send(std::move(res));
}

void HttpSession::handle_api(const std::string& target) {
  const auto now = server_->now();
  const bool post = req_.method() == http::verb::post;
  // Every POST and the WebSocket come from this server's own page: the
  // browser's Origin says so (another site's page cannot forge it).
  if ((post || websocket::is_upgrade(req_)) && !check_origin()) return;
  if (target == "/api/session" && req_.method() == http::verb::get) {
    const Session* s = session();
    if (!s && server_->opt.login == ipc::WebLogin::None) {
      // No login: a session for whoever asks (loopback addresses only,
      // cell_config.cpp); it still carries the CSRF token.
      auto [token, csrf] = server_->sessions.open(now);
      http::response<http::string_body> res{http::status::ok, req_.version()};
      res.set(http::field::set_cookie, cookie(token));
      res.set(http::field::content_type, "application/json");
      res.body() = R"({"session":true,"csrf":")" + csrf + R"(","login":"none"})";
      return send(std::move(res));
    }
    std::string out = R"({"session":)";
    out += s ? "true" : "false";
    if (s) out += R"(,"csrf":")" + s->csrf + '"';
    out += R"(,"login":")" + server_->login_name + R"("})";
    return send_json(http::status::ok, out);
  }
  if (target == "/api/login" && post) return login(now);
  const Session* s = session();
  if (!s) {
    server_->count([](WebCounters& c) { ++c.no_session; });
    return refuse(http::status::unauthorized, "log in first");
  }
  if (target == "/api/logout" && post) {
    const auto it = req_.find(http::field::cookie);
    server_->sessions.close(cookie_value(std::string(it->value()), kCookie));
    return send_json(http::status::ok, R"({"session":false})");
  }
  if (target == "/api/ws" && websocket::is_upgrade(req_)) {
    auto page = std::make_shared<WsSession>(server_, std::move(stream_));
    server_->connections.erase(this);  // the page counts from now
    page->accept(std::move(req_));
    return;
  }
  if (target == "/api/counters" && req_.method() == http::verb::get)
    return send_json(http::status::ok, server_->counters_json());
  if (target == "/api/command" && post) {
    // A write from another site's page fails the Origin check already; the
    // token (which such a page cannot read) is the second lock.
    if (sv(req_["X-CSRF-Token"]) != s->csrf) {
      server_->count([](WebCounters& c) { ++c.bad_csrf; });
      return refuse(http::status::forbidden, "missing or wrong X-CSRF-Token");
    }
    CommandBody body;
    std::string err;
    if (!parse_command_body(req_.body(), body, err)) return refuse(http::status::bad_request, err);
    if (server_->opt.read_only && changes_cell(body.verb)) {
      server_->count([](WebCounters& c) { ++c.read_only_refused; });
      return send_json(http::status::ok,
                       json_refusal("'" + body.verb +
                                    "' is not allowed: the web HMI is read-only (hmi: web: "
                                    "read_only)"));
    }
    if (body.verb == "ack") {
      if (body.args.size() != 1) return refuse(http::status::bad_request, "ack: needs ID or all");
      return send_json(http::status::ok, server_->acknowledge(body.args[0]));
    }
    softplc_hmi::command_t c{};
    c.request_id = server_->next_request++;
    c.client = "web";
    c.verb = body.verb;
    c.args = body.args;
    c.n_args = int(c.args.size());
    if (!server_->bridge.submit(c))
      return refuse(http::status::service_unavailable, "busy: too many commands waiting");
    server_->count([](WebCounters& c) { ++c.commands; });
    waiting_for_ = c.request_id;
    server_->waiting[c.request_id] = shared_from_this();
    reply_timer_.expires_after(kReplyTimeout);
    reply_timer_.async_wait([self = shared_from_this(), id = c.request_id](beast::error_code ec) {
      if (ec) return;
      if (self->server_->waiting.erase(id))
        self->answer(http::status::gateway_timeout,
                     json_refusal("no answer from the cell within 5 s"));
    });
    return;
  }
  refuse(http::status::not_found, "no such request");
}

void HttpSession::login(std::chrono::steady_clock::time_point now) {
  // A locked-out address is answered before the password is looked at:
  // neither a right guess nor the hash's cost is there for it to measure.
  if (const auto wait = server_->login_limiter.locked_for(client_, now); wait.count() > 0) {
    server_->count([](WebCounters& c) { ++c.login_locked; });
    http::response<http::string_body> res{http::status::too_many_requests, req_.version()};
    res.set(http::field::retry_after, std::to_string(wait.count()));
    res.set(http::field::content_type, "application/json");
    res.body() = json_refusal("too many failed logins from this address: try again in " +
                              std::to_string(wait.count()) + " s");
    return send(std::move(res));
  }
  const std::string& password = req_.body();
  bool ok = false;
  if (password.size() <= kMaxPassword) {
    if (server_->opt.login == ipc::WebLogin::Hash)
      ok = verify_password(password, server_->opt.password_hash);
    else if (server_->opt.login == ipc::WebLogin::Key && server_->opt.key)
      ok = verify_key_text(password, *server_->opt.key);
  }
  if (!ok) {
    server_->login_limiter.failed(client_, now);
    server_->count([](WebCounters& c) { ++c.login_failed; });
    return refuse(http::status::unauthorized, "wrong password");
  }
  server_->login_limiter.succeeded(client_);
  server_->count([](WebCounters& c) { ++c.logins; });
  auto [token, csrf] = server_->sessions.open(now);
  http::response<http::string_body> res{http::status::ok, req_.version()};
  res.set(http::field::set_cookie, cookie(token));
  res.set(http::field::content_type, "application/json");
  res.body() = R"({"session":true,"csrf":")" + csrf + R"("})";
  send(std::move(res));
}

}  // namespace plc::hmi::web

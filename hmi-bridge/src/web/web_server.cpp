#include "plc/hmi/web/web_server.hpp"

#include <openssl/crypto.h>
#include <pthread.h>

#include <cstring>
#include <stdexcept>

#include "plc/hmi/web/json.hpp"
#include "web_impl.hpp"

namespace plc::hmi::web {

WebServer::Impl::Impl(Bridge& b, WebOptions o) : bridge(b), opt(std::move(o)) {
  login_name = opt.login == ipc::WebLogin::None  ? "none"
               : opt.login == ipc::WebLogin::Key ? "key"
                                                 : "password";
}

WebServer::Impl::~Impl() {
  // Sessions hold sockets of `io`: they go first, then what the queue holds.
  pages.clear();
  waiting.clear();
  acceptor.reset();
  io.reset();
}

void WebServer::Impl::shut_down() {
  beast::error_code ignored;
  if (acceptor) acceptor->close(ignored);
  const std::vector<std::shared_ptr<WsSession>> open(pages.begin(), pages.end());
  for (const auto& p : open) p->close();
  const std::vector<HttpSession*> conns(connections.begin(), connections.end());
  for (HttpSession* c : conns) c->close();
  waiting.clear();
}

std::string WebServer::Impl::counters_json() const {
  WebCounters c;
  {
    std::lock_guard<std::mutex> lock(counters_mu);
    c = counters;
  }
  std::string out = "{";
  auto f = [&out](const char* k, std::uint64_t v) {
    out += '"';
    out += k;
    out += "\":";
    out += std::to_string(v);
    out += ',';
  };
  f("connections", c.connections);
  f("tls_failed", c.tls_failed);
  f("refused_connections", c.refused_connections);
  f("pages", c.pages);
  f("sent", c.sent);
  f("dropped", c.dropped);
  f("slow_pages", c.slow_pages);
  f("backlog_dropped", c.backlog_dropped);
  f("logins", c.logins);
  f("login_failed", c.login_failed);
  f("login_locked", c.login_locked);
  f("no_session", c.no_session);
  f("bad_origin", c.bad_origin);
  f("bad_host", c.bad_host);
  f("bad_csrf", c.bad_csrf);
  f("too_large", c.too_large);
  f("commands", c.commands);
  f("read_only_refused", c.read_only_refused);
  out.back() = '}';
  return out;
}

void WebServer::Impl::accept() {
  acceptor->async_accept([this](beast::error_code ec, tcp::socket s) {
    if (ec == asio::error::operation_aborted || !acceptor->is_open()) return;
    if (!ec) {
      if (connections.size() + pages.size() >= opt.max_connections) {
        count([](WebCounters& c) { ++c.refused_connections; });
        beast::error_code ignored;
        s.close(ignored);
      } else {
        count([](WebCounters& c) { ++c.connections; });
        std::make_shared<HttpSession>(this, std::move(s))->run();
      }
    }
    accept();
  });
}

void WebServer::Impl::broadcast(const Message& m) {
  // send() may close a page, which erases it from `pages`.
  const std::vector<std::shared_ptr<WsSession>> now(pages.begin(), pages.end());
  for (const auto& p : now) p->send(m);
}

void WebServer::Impl::open_page(const std::shared_ptr<WsSession>& page) {
  pages.insert(page);
  count([this](WebCounters& c) { c.pages = pages.size(); });
  if (desc) page->send(desc);
  // What the page missed: the latest value of every variable, as one full
  // message of no task in particular.
  std::string v = R"({"t":"values","task":"","scan":0,"full":true,"v":[)";
  for (const auto& [index, tn] : latest) {
    v += '[';
    v += std::to_string(index);
    v += ',';
    append_string(v, tn.first);
    v += ',';
    append_number(v, tn.second);
    v += "],";
  }
  if (v.back() == ',') v.pop_back();
  v += "]}";
  page->send(std::make_shared<const std::string>(std::move(v)));
  if (stats) page->send(stats);
  if (diag) page->send(diag);
  for (const auto& a : alarms) page->send(a.json);
}

std::string WebServer::Impl::acknowledge(const std::string& which) {
  int n = 0;
  for (Alarm& a : alarms) {
    if (a.acked || (which != "all" && which != std::to_string(a.id))) continue;
    a.acked = true;
    a.json = std::make_shared<const std::string>(alarm_json(a.alarm, a.id, true));
    broadcast(
        std::make_shared<const std::string>(R"({"t":"ack","id":)" + std::to_string(a.id) + "}"));
    ++n;
  }
  if (n == 0) return R"({"ok":false,"refusal":"no such alarm to acknowledge"})";
  return R"({"ok":true,"text":"acknowledged )" + std::to_string(n) + R"("})";
}

// ---------------------------------------------------------------- the tap
// (the bridge's thread: copy, post, return)

void WebServer::on_description(const softplc_hmi::cell_description_t& d) {
  impl_->post(
      [s = impl_.get(), d]() {
        // Every second the same one: pages hear of a new layout only.
        if (s->desc && d.layout_hash == s->desc_layout && d.cell == s->desc_cell) return;
        s->desc_layout = d.layout_hash;
        s->desc_cell = d.cell;
        s->latest.clear();
        s->desc = std::make_shared<const std::string>(
            description_json(d, s->opt.read_only, s->login_name));
        s->broadcast(s->desc);
      },
      false);
}

void WebServer::on_values(const softplc_hmi::values_t& v, const softplc_hmi::trace_sample_t& t) {
  impl_->post(
      [s = impl_.get(), v, t]() {
        for (std::size_t i = 0; i < v.values.size(); ++i)
          s->latest[v.values[i].index].first = v.values[i].text;
        for (std::size_t i = 0; i < t.index.size() && i < t.value.size(); ++i)
          if (auto it = s->latest.find(t.index[i]); it != s->latest.end())
            it->second.second = t.value[i];
        s->broadcast(std::make_shared<const std::string>(values_json(v, t)));
      },
      true);
}

void WebServer::on_stats(const softplc_hmi::stats_t& m) {
  impl_->post(
      [s = impl_.get(), m]() {
        s->stats = std::make_shared<const std::string>(stats_json(m, s->counters_json()));
        s->broadcast(s->stats);
      },
      false);
}

void WebServer::on_diagnostics(const softplc_hmi::diagnostics_t& m) {
  impl_->post(
      [s = impl_.get(), m]() {
        s->diag = std::make_shared<const std::string>(diagnostics_json(m));
        s->broadcast(s->diag);
      },
      false);
}

void WebServer::on_alarm(const softplc_hmi::alarm_t& a) {
  impl_->post(
      [s = impl_.get(), a]() {
        const std::int64_t id = s->next_alarm++;
        auto m = std::make_shared<const std::string>(alarm_json(a, id, false));
        s->alarms.push_back({id, a, false, m});
        if (s->alarms.size() > kAlarmHistory) s->alarms.pop_front();
        s->broadcast(m);
      },
      false);
}

void WebServer::on_reply(const softplc_hmi::reply_t& r) {
  if (r.client != "web") return;
  impl_->post(
      [s = impl_.get(), r]() {
        const auto it = s->waiting.find(r.request_id);
        if (it == s->waiting.end()) return;  // timed out meanwhile
        auto session = it->second;
        s->waiting.erase(it);
        session->answer(http::status::ok, reply_json(r));
      },
      false);
}

// ---------------------------------------------------------------- WebServer

namespace {

std::string bounded(const char* s, std::size_t cap) { return std::string(s, strnlen(s, cap)); }

}  // namespace

WebOptions web_options(const ipc::Settings& settings) {
  WebOptions o;
  o.address = bounded(settings.web_address, sizeof settings.web_address);
  o.port = settings.web_port;
  o.read_only = settings.web_read_only != 0;
  o.login = ipc::WebLogin(settings.web_login);
  o.password_hash = bounded(settings.web_password_hash, sizeof settings.web_password_hash);
  if (settings.has_key) {
    Key k;
    std::memcpy(k.data(), settings.key, k.size());
    o.key = k;
  }
  o.tls_cert_pem = bounded(settings.web_tls_cert, sizeof settings.web_tls_cert);
  o.tls_key_pem = bounded(settings.web_tls_key, sizeof settings.web_tls_key);
  return o;
}

WebServer::WebServer(Bridge& bridge, WebOptions options)
    : impl_(std::make_unique<Impl>(bridge, std::move(options))) {
  Impl& s = *impl_;
  beast::error_code ec;
  const auto address = asio::ip::make_address(s.opt.address, ec);
  const std::string where =
      "hmi: web: cannot listen on " + s.opt.address + " port " + std::to_string(s.opt.port) + ": ";
  if (ec) throw std::runtime_error(where + ec.message());
  const tcp::endpoint ep(address, static_cast<unsigned short>(s.opt.port));
  s.acceptor.emplace(*s.io);
  s.acceptor->open(ep.protocol(), ec);
  if (!ec) s.acceptor->set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) s.acceptor->bind(ep, ec);
  if (!ec) s.acceptor->listen(asio::socket_base::max_listen_connections, ec);
  if (ec) throw std::runtime_error(where + ec.message());
  if (!s.opt.tls_cert_pem.empty() || !s.opt.tls_key_pem.empty()) {
    // TLS 1.2 at least (no SSLv3, TLS 1.0, 1.1); the certificate and key as
    // plcrun read them (hmi: web: tls:), from memory: plchmi opens no file.
    namespace ssl = asio::ssl;
    s.tls.emplace(ssl::context::tls_server);
    s.tls->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 |
                       ssl::context::no_sslv3 | ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 |
                       ssl::context::single_dh_use);
    if (SSL_CTX_set_min_proto_version(s.tls->native_handle(), TLS1_2_VERSION) != 1)
      throw std::runtime_error("hmi: web: tls: cannot require TLS 1.2");
    s.tls->use_certificate_chain(asio::buffer(s.opt.tls_cert_pem), ec);
    if (ec) throw std::runtime_error("hmi: web: tls: the certificate: " + ec.message());
    s.tls->use_private_key(asio::buffer(s.opt.tls_key_pem), ssl::context::pem, ec);
    if (ec) throw std::runtime_error("hmi: web: tls: the private key: " + ec.message());
    OPENSSL_cleanse(s.opt.tls_key_pem.data(), s.opt.tls_key_pem.size());
    s.opt.tls_key_pem.clear();
  }
  s.port = s.acceptor->local_endpoint().port();
  s.hosts = allowed_hosts(s.opt.address, s.port);
}

WebServer::~WebServer() { stop(); }

int WebServer::port() const { return impl_->port; }

WebCounters WebServer::counters() const {
  std::lock_guard<std::mutex> lock(impl_->counters_mu);
  return impl_->counters;
}

void WebServer::start() {
  Impl& s = *impl_;
  s.accept();
  s.thread = std::thread([&s] { s.io->run(); });
  pthread_setname_np(s.thread.native_handle(), "plchmi-web");  // top -H, the benchmark
}

void WebServer::stop() {
  Impl& s = *impl_;
  if (!s.thread.joinable()) return;
  // Everything closed on the io thread, then its loop ends.
  asio::post(*s.io, [&s] {
    s.shut_down();
    s.io->stop();  // what the closing left in the queue goes with ~Impl
  });
  s.thread.join();
}

}  // namespace plc::hmi::web

// The web HMI over TLS (issue 27, hmi: web: tls:, docs/config.md): with a
// self-signed certificate made here by the openssl CLI, plcrun's half (Host)
// reads and checks the files and hands their PEM texts over in the state
// region; the server built from those settings (web_options, as plchmi
// does) serves a login, a command and a WebSocket over HTTPS/WSS only,
// the cookie marked Secure; a plain HTTP request to its port gets no
// answer. A key file others may read, a key of another certificate, a
// missing or non-PEM file is a config error at the key's line.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <boost/asio/ssl.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <cstdlib>
#include <fstream>
#include <future>

#include "../hmi/hmi_test_cell.hpp"
#include "plc/hmi/tls_files.hpp"
#include "plc/hmi/web/web_auth.hpp"
#include "plc/hmi/web/web_server.hpp"
#include "served_cell.hpp"
#include "web_client.hpp"

using namespace plc;
namespace asio = webtest::asio;
namespace beast = webtest::beast;
namespace http = webtest::http;
namespace ssl = boost::asio::ssl;
namespace websocket = beast::websocket;

namespace {

constexpr const char* kPassword = "s3cret-for-tls";

std::string dir() { return ::testing::TempDir() + "web_tls_"; }

// A fresh EC key and self-signed certificate for 127.0.0.1 (1 day).
void make_cert(const std::string& name) {
  const std::string cmd =
      "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 "
      "-nodes -days 1 -subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1 "
      "-keyout " +
      dir() + name + ".key -out " + dir() + name + ".crt 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  ::chmod((dir() + name + ".key").c_str(), 0600);
}

std::string tls_section(const std::string& cert, const std::string& key) {
  return std::string(plctest::kHmiSection) + "  web:\n    login: \"" +
         hmi::web::hash_password(kPassword, 1000) + "\"\n    tls:\n      cert: " + cert +
         "\n      key: " + key + "\n";
}

// The server of a cell whose hmi: web: tls: names `name`.crt and .key.
struct TlsCell : webtest::ServedCell {
  explicit TlsCell(const std::string& name)
      : ServedCell(tls_section(dir() + name + ".crt", dir() + name + ".key")) {
    serve(hmi::web::web_options(h.host->regions().settings()), "https");
  }
};

// A client that trusts only the test's certificate and checks the name.
ssl::context client_context(const std::string& name) {
  ssl::context ctx(ssl::context::tls_client);
  ctx.load_verify_file(dir() + name + ".crt");
  ctx.set_verify_mode(ssl::verify_peer);
  return ctx;
}

webtest::Response https(const std::string& name, int port, http::verb method,
                        const std::string& target, std::map<std::string, std::string> headers,
                        const std::string& body = "") {
  asio::io_context ioc;
  auto ctx = client_context(name);
  ssl::stream<webtest::tcp::socket> s(ioc, ctx);
  s.set_verify_callback(ssl::host_name_verification("127.0.0.1"));
  s.next_layer().connect({asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
  webtest::set_timeout(s.next_layer().native_handle(), 10000);
  beast::error_code ec;
  s.handshake(ssl::stream_base::client, ec);
  if (ec) return {};
  http::request<http::string_body> req{method, target, 11};
  req.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  for (const auto& [k, v] : headers) req.set(k, v);
  req.body() = body;
  req.prepare_payload();
  http::write(s, req, ec);
  beast::flat_buffer buf;
  http::response<http::string_body> res;
  if (!ec) http::read(s, buf, res, ec);
  webtest::Response r;
  if (ec) return r;
  r.status = res.result_int();
  r.body = res.body();
  r.set_cookie = std::string(res[http::field::set_cookie]);
  return r;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(WebHmiTls, HttpsLoginCommandAndWss) {
  make_cert("good");
  TlsCell w("good");
  const auto login =
      https("good", w.port(), http::verb::post, "/api/login", {{"Origin", w.origin}}, kPassword);
  ASSERT_EQ(login.status, 200) << login.body;
  EXPECT_TRUE(has(login.set_cookie, "; Secure")) << login.set_cookie;
  const std::string cookie = login.set_cookie.substr(0, login.set_cookie.find(';'));
  const std::string csrf = login.body.substr(login.body.find("\"csrf\":\"") + 8, 64);
  // A command over HTTPS, applied by the cell.
  const auto r = w.pump([&] {
    return https("good", w.port(), http::verb::post, "/api/command",
                 {{"Origin", w.origin}, {"Cookie", cookie}, {"X-CSRF-Token", csrf}},
                 "write\nTank.high_level\n4321");
  });
  EXPECT_EQ(r.status, 200);
  EXPECT_TRUE(has(r.body, "\"ok\":true")) << r.body;
  // Applied at the next scan of its task, some base ticks on (bounded).
  for (int i = 0; i < 100 && w.h.dbg->read({"Tank.high_level"}).front().text != "4321"; ++i)
    w.round();
  EXPECT_EQ(w.h.dbg->read({"Tank.high_level"}).front().text, "4321");
  // The page's WebSocket over TLS: its first message is the cell's picture.
  asio::io_context ioc;
  auto ctx = client_context("good");
  websocket::stream<ssl::stream<webtest::tcp::socket>> ws(ioc, ctx);
  ws.next_layer().set_verify_callback(ssl::host_name_verification("127.0.0.1"));
  beast::get_lowest_layer(ws).connect(
      {asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(w.port())});
  webtest::set_timeout(beast::get_lowest_layer(ws).native_handle(), 10000);
  ws.next_layer().handshake(ssl::stream_base::client);
  ws.set_option(websocket::stream_base::decorator([&](websocket::request_type& req) {
    req.set(http::field::origin, w.origin);
    req.set(http::field::cookie, cookie);
  }));
  ws.handshake("127.0.0.1:" + std::to_string(w.port()), "/api/ws");
  beast::flat_buffer in;
  ws.read(in);
  const std::string first = beast::buffers_to_string(in.data());
  EXPECT_EQ(first.rfind("{\"t\":", 0), 0U) << first;
  EXPECT_EQ(w.web->counters().tls_failed, 0U);
}

TEST(WebHmiTls, PlainHttpToTheTlsPortGetsNoAnswer) {
  make_cert("plain");
  TlsCell w("plain");
  EXPECT_EQ(webtest::request(w.port(), http::verb::get, "/", {}).status, 0);
  // The control: the same request over TLS is served.
  EXPECT_EQ(https("plain", w.port(), http::verb::get, "/", {}).status, 200);
  EXPECT_EQ(w.web->counters().tls_failed, 1U);
}

TEST(WebHmiTls, BadFilesAreLocatedConfigErrors) {
  make_cert("a");
  make_cert("b");
  auto error_of = [](const std::string& cert, const std::string& key) -> std::string {
    try {
      plctest::HmiCell h(tls_section(cert, key));
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  };
  // The lines of cert: and key: in the config HmiCell parses.
  const std::string text = plctest::demo_yaml() + tls_section("C", "K");
  const auto line_of = [&](const std::string& what) {
    const auto at = text.find(what);
    return "hmi_test.yaml:" +
           std::to_string(std::count(text.begin(), text.begin() + at, '\n') + 1) + ":";
  };
  const std::string cert_at = line_of("cert: C"), key_at = line_of("key: K");
  const std::string a_crt = dir() + "a.crt", a_key = dir() + "a.key", b_key = dir() + "b.key";
  EXPECT_EQ(error_of(a_crt, a_key), "");
  std::string e = error_of(a_crt, b_key);
  EXPECT_TRUE(has(e, key_at + "12: key 'key': key file")) << e;
  EXPECT_TRUE(has(e, "is not the key of the certificate")) << e;
  ::chmod(a_key.c_str(), 0644);
  e = error_of(a_crt, a_key);
  ::chmod(a_key.c_str(), 0600);
  EXPECT_TRUE(has(e, key_at)) << e;
  EXPECT_TRUE(has(e, "readable or writable by group or others (mode 0644)")) << e;
  EXPECT_TRUE(has(e, "chmod 600")) << e;
  e = error_of(dir() + "missing.crt", a_key);
  EXPECT_TRUE(has(e, cert_at + "13: key 'cert': cannot read certificate file")) << e;
  e = error_of(a_key, a_key);  // a key is no certificate
  EXPECT_TRUE(has(e, cert_at)) << e;
  EXPECT_TRUE(has(e, "holds no PEM certificate")) << e;
  const std::string crt_as_key = dir() + "crt_as.key";
  std::ofstream(crt_as_key) << std::ifstream(a_crt).rdbuf();
  ::chmod(crt_as_key.c_str(), 0600);
  e = error_of(a_crt, crt_as_key);  // nor a certificate a key
  EXPECT_TRUE(has(e, key_at)) << e;
  EXPECT_TRUE(has(e, "holds no unencrypted PEM private key")) << e;
}

// A certificate outside its validity period (made for 1 day; `now` moved
// 2 days on or back) loads with a warning, not an error: browsers refuse
// it, but an HMI certificate never keeps a cell from starting.
TEST(WebHmiTls, CertificateOutsideItsValidityLoadsWithAWarning) {
  make_cert("valid");
  const std::string crt = dir() + "valid.crt", key = dir() + "valid.key";
  const std::time_t now = std::time(nullptr), two_days = 2 * 24 * 3600;
  hmi::TlsFilesError err;
  auto f = hmi::load_tls_files(crt, key, err, now);
  ASSERT_TRUE(f) << err.message;
  EXPECT_EQ(f->warning, "");
  f = hmi::load_tls_files(crt, key, err, now + two_days);
  ASSERT_TRUE(f) << err.message;
  EXPECT_TRUE(has(f->warning, "certificate in '" + crt + "' expired on ")) << f->warning;
  EXPECT_TRUE(has(f->warning, " GMT: browsers will refuse it")) << f->warning;
  f = hmi::load_tls_files(crt, key, err, now - two_days);
  ASSERT_TRUE(f) << err.message;
  EXPECT_TRUE(has(f->warning, "is not valid before ")) << f->warning;
}

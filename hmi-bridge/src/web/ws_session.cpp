// One page's WebSocket (hmi-bridge/README.md "Web HMI"): the server sends,
// the page only listens. A page whose queue is full is disconnected: it
// reconnects and starts from a full picture, where dropping single delta
// messages would leave it showing old values.
#include "web_impl.hpp"

namespace plc::hmi::web {

namespace {

WsStream make_ws(Stream&& s) {
  if (auto* plain = std::get_if<PlainStream>(&s))
    return WsStream(std::in_place_index<0>, std::move(*plain));
  return WsStream(std::in_place_index<1>, std::move(std::get<TlsStream>(s)));
}

}  // namespace

WsSession::WsSession(WebServer::Impl* server, Stream&& stream)
    : server_(server), ws_(make_ws(std::move(stream))) {}

beast::tcp_stream& WsSession::tcp() {
  return std::visit([](auto& w) -> beast::tcp_stream& { return beast::get_lowest_layer(w); }, ws_);
}

void WsSession::accept(http::request<http::string_body> req) {
  tcp().expires_never();  // the WebSocket's own timeouts from here
  websocket::stream_base::timeout t{};
  t.handshake_timeout = std::chrono::seconds(10);
  t.idle_timeout = std::chrono::seconds(20);  // a page that answers no ping goes
  t.keep_alive_pings = true;
  std::visit(
      [&](auto& ws) {
        ws.set_option(t);
        ws.read_message_max(kMaxWsIn);
        ws.set_option(websocket::stream_base::decorator(
            [](websocket::response_type& res) { res.set(http::field::server, "plchmi"); }));
        ws.async_accept(req, [self = shared_from_this()](beast::error_code ec) {
          if (ec) return;
          self->open_ = true;
          self->server_->open_page(self);
          self->read();
        });
      },
      ws_);
}

void WsSession::read() {
  std::visit(
      [this](auto& ws) {
        ws.async_read(in_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
          if (ec) {
            if (ec == websocket::error::message_too_big)
              self->server_->count([](WebCounters& c) { ++c.too_large; });
            return self->close();
          }
          self->in_.clear();  // the page has nothing to say: read only to see it close
          self->read();
        });
      },
      ws_);
}

void WsSession::send(const Message& m) {
  if (closed_) return;
  if (queue_.size() >= server_->opt.max_queue_messages ||
      queued_bytes_ + m->size() > server_->opt.max_queue_bytes) {
    server_->count([n = queue_.size()](WebCounters& c) {
      c.dropped += n + 1;
      ++c.slow_pages;
    });
    return close();
  }
  queue_.push_back(m);
  queued_bytes_ += m->size();
  if (!writing_) write();
}

void WsSession::write() {
  writing_ = true;
  std::visit(
      [this](auto& ws) {
        ws.text(true);
        ws.async_write(asio::buffer(*queue_.front()),
                       [self = shared_from_this()](beast::error_code ec, std::size_t) {
                         self->writing_ = false;
                         if (ec || self->closed_) return self->close();
                         self->server_->count([](WebCounters& c) { ++c.sent; });
                         self->queued_bytes_ -= self->queue_.front()->size();
                         self->queue_.pop_front();
                         if (!self->queue_.empty()) self->write();
                       });
      },
      ws_);
}

void WsSession::close() {
  if (closed_) return;
  closed_ = true;
  queue_.clear();
  queued_bytes_ = 0;
  // The socket, not a close handshake: a page that does not read would
  // never complete one.
  beast::error_code ignored;
  tcp().socket().shutdown(tcp::socket::shutdown_both, ignored);
  tcp().close();
  server_->pages.erase(shared_from_this());
  server_->count([n = server_->pages.size()](WebCounters& c) { c.pages = n; });
}

}  // namespace plc::hmi::web

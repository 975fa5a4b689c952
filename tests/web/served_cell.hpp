// The demo cell and its bridge in lockstep on the test's thread
// (hmi_test_cell.hpp) with the web server as plchmi runs it (its own
// thread, loopback, any free port): the fixture the web tests share.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <memory>
#include <string>
#include <utility>

#include "../hmi/hmi_test_cell.hpp"
#include "plc/hmi/web/web_server.hpp"

namespace webtest {

struct ServedCell {
  plctest::HmiCell h;
  std::unique_ptr<plc::hmi::web::WebServer> web;
  std::string origin;

  template <class... Args>
  explicit ServedCell(Args&&... cell_args) : h(std::forward<Args>(cell_args)...) {}
  ~ServedCell() {
    if (!web) return;
    h.bridge->set_tap(nullptr);
    web->stop();
  }
  ServedCell(const ServedCell&) = delete;
  ServedCell& operator=(const ServedCell&) = delete;

  // Starts the server with `o` on a free port; `scheme` is the page's
  // ("http" or "https"), for the Origin the server expects.
  void serve(plc::hmi::web::WebOptions o, const std::string& scheme) {
    o.port = 0;
    web = std::make_unique<plc::hmi::web::WebServer>(*h.bridge, o);
    h.bridge->set_tap(web.get());
    web->start();
    origin = scheme + "://127.0.0.1:" + std::to_string(web->port());
    round();
  }
  int port() const { return web->port(); }
  // One scan of the cell and one bridge round.
  void round() {
    ASSERT_TRUE(h.dbg->step(1).ok);
    h.bridge->service();
  }
  // `f` on another thread while this one runs the cell and the bridge (a
  // command's answer needs both), at most 5,000 rounds.
  template <class F>
  auto pump(F f) {
    auto fut = std::async(std::launch::async, f);
    for (int i = 0;
         i < 5000 && fut.wait_for(std::chrono::milliseconds(1)) != std::future_status::ready; ++i)
      round();
    return fut.get();
  }
};

}  // namespace webtest

// The demo cell with an `hmi:` section, a debugger over it, plcrun's HMI host
// and a bridge on memq:// over the host's shared memory, both halves in
// lockstep on the test's thread (in-process, deterministic): what the
// bridge tests share. plcrun runs the bridge as its own process (plchmi);
// here the same two halves meet through the same shared memory, without
// the process boundary, so that virtual time stays reproducible.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "plc/cell_config.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/hmi/bridge.hpp"
#include "plc/hmi/checked_decode.hpp"
#include "plc/hmi/host.hpp"
#include "plc_test_paths.hpp"
#include "softplc_hmi/command_t.hpp"
#include "softplc_hmi/reply_t.hpp"
#include "softplc_hmi/values_t.hpp"

namespace plctest {

inline std::string demo_yaml() {
  std::ifstream f(source_path("programs/demo/cell.yaml"));
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

inline const char* kHmiSection = R"(
hmi:
  url: memq://
  rate: 100
  publish: ["Tank.*", "Supervisor.enable", "%QW0"]
  writable: ["Tank.high_level", "Tank.low_level", "%QW0"]
  forceable: ["Tank.enable"]
)";

// A virtual-time debugger session of the demo cell with its bridge.
struct HmiCell {
  // Declared first: they outlive the bridge's transport that calls them.
  struct ValuesSink {
    HmiCell* h;
    void on(const softplc_hmi::values_t& m) {
      for (const auto& v : m.values) h->seen[v.index] = v.text;
    }
  } values_sink{this};
  struct ReplySink {
    HmiCell* h;
    void on(const softplc_hmi::reply_t& r) { h->replies.push_back(r); }
  } reply_sink{this};
  plc::CellConfig cfg;
  std::unique_ptr<plc::hmi::Host> host;
  std::unique_ptr<plc::debug::Debugger> dbg;
  std::unique_ptr<plc::hmi::Bridge> bridge;
  std::map<int, std::string> seen;   // index -> last value text received
  std::map<std::string, int> index;  // path -> index
  std::vector<softplc_hmi::reply_t> replies;

  // `base`: the cell without its hmi: section (default: the demo cell).
  // `before_build`: called with the host before the first build (what
  // plcrun notes before the first scan: a start alarm).
  explicit HmiCell(const std::string& hmi = kHmiSection, const std::string& key_file = "",
                   const std::string& base = demo_yaml(),
                   const std::function<void(plc::hmi::Host&)>& before_build = {}) {
    std::string text = base + hmi;
    if (!key_file.empty()) text += "  key_file: " + key_file + "\n";
    cfg = plc::parse_cell_config(text, "hmi_test.yaml");
    plc::hmi::Host::Options ho;
    ho.mode = plc::hmi::Host::Mode::Lockstep;
    host = std::make_unique<plc::hmi::Host>(cfg.hmi, cfg.file, ho);
    if (before_build) before_build(*host);
    plc::debug::Debugger::Options o;
    o.span = std::chrono::minutes(10);
    o.on_build = [this](plc::Runtime& rt) { host->attach(rt); };
    dbg = std::make_unique<plc::debug::Debugger>(
        [this] { return std::make_unique<plc::Runtime>(cfg); }, o);
    host->set_debugger(dbg.get());
    bridge = std::make_unique<plc::hmi::Bridge>(host->regions().view());
    bridge->set_peer([this] { host->round(); });
    host->on_new_regions([this] { bridge->attach(host->regions().view()); });
    // memq:// queues per transport: the test's subscriptions are on the
    // bridge's transport, added here before anything handles it; the
    // bridge's thread is never started (the test drives service() itself),
    // so one thread subscribes, handles and publishes (the transport's rule).
    plc::hmi::subscribe_checked<softplc_hmi::values_t>(bridge->transport(),
                                                       bridge->channels().values, &values_sink);
    plc::hmi::subscribe_checked<softplc_hmi::reply_t>(bridge->transport(), bridge->channels().reply,
                                                      &reply_sink);
  }
  ~HmiCell() {
    if (bridge) bridge->stop();
  }

  // Sends c as a client would, lets the bridge serve it, returns its one
  // reply (or fails the test).
  softplc_hmi::reply_t send(const softplc_hmi::command_t& c) {
    replies.clear();
    bridge->transport().publish(bridge->channels().cmd, &c);
    bridge->service();
    EXPECT_EQ(replies.size(), 1U) << c.verb;
    return replies.empty() ? softplc_hmi::reply_t{} : replies.front();
  }
  // The variable's value as the debugger reads it (IEC text).
  std::string value_of(const std::string& path) { return dbg->read({path}).front().text; }
};

}  // namespace plctest

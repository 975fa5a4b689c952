// The HMI bridge: publishes a running cell's variables, statistics and
// diagnostics over LCM and serves commands through the debugger's typed API
// (hmi-bridge/README.md). Configured by the cell's `hmi:` section.
//
// Threads: the scan threads only copy values into a ScanSnapshot when asked
// (one atomic load per scan otherwise). Everything else - encoding,
// publishing, receiving and serving commands - happens on the bridge's one
// thread (the transport's rule: handle and subscribe from one thread), or on
// the caller's thread when a test drives service() itself.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "plc/cell_config.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/hmi/channels.hpp"
#include "plc/hmi/command_auth.hpp"
#include "plc/hmi/scan_snapshot.hpp"
#include "plc/hmi/transport.hpp"
#include "softplc_hmi/alarm_t.hpp"
#include "softplc_hmi/cell_description_t.hpp"
#include "softplc_hmi/command_t.hpp"
#include "softplc_hmi/reply_t.hpp"

namespace plc::hmi {

struct BridgeCounters {
  std::uint64_t published = 0;  // values_t messages sent
  std::uint64_t dropped = 0;    // publish ticks missed because the bridge was late
  std::uint64_t commands = 0;   // commands applied
  std::uint64_t refused = 0;    // refused: access, unknown verb, the debugger said no
  std::uint64_t bad_tag = 0;    // HMAC did not verify (or missing with a key)
  std::uint64_t replayed = 0;   // counter not above the client's last one
  std::uint64_t malformed = 0;  // did not decode as a command_t
};

// Pattern match over variable paths and addresses: `*` any run of
// characters (dots included), `?` any one character; `[` and `]` are
// literal, so `Cell.axes[0].*` matches the paths --list-vars prints for an
// array element; `\` escapes the next character.
bool pattern_matches(const std::string& pattern, const std::string& text);

class Bridge {
 public:
  // Throws ConfigError (file:line:col) for a pattern that matches no
  // variable, a key file that cannot be used, or a url that is wrong or
  // cannot be opened. `cell_file` names the config in errors.
  Bridge(const HmiConfig& cfg, std::string cell_file);
  ~Bridge();
  Bridge(const Bridge&) = delete;
  Bridge& operator=(const Bridge&) = delete;

  // Before the runtime's first scan (debug::Debugger::Options::on_build):
  // resolves the patterns and adds the scan observers. Again after a
  // rebuild (goto, restart).
  void attach(Runtime& rt);
  // Commands are served through this debugger (none: every command is
  // refused with a reason).
  void set_debugger(debug::Debugger* d) { dbg_ = d; }

  // The bridge's thread: serve commands, publish at the configured rate,
  // statistics and diagnostics at 1 Hz.
  void start();
  void stop();

  // One round on the caller's thread (tests, virtual time): handles every
  // command waiting (up to a bound), publishes the snapshots the scans
  // have filled since the last round and an alarm for each device state
  // change since then. Returns the values_t messages sent.
  int service(int wait_ms = 0);
  void publish_stats();
  void publish_diagnostics();
  void publish_description();
  // Publishes an alarm_t on PREFIX_ALARM for every device whose state, as
  // its task's scans saw it, changed since the last call (lost, back), and
  // remembers it for diagnostics_t. Returns how many.
  int publish_device_alarms();

  // An alarm that holds for the whole run, noted at start-up (kind
  // `retain_cold_start`: a warm start that fell back to a cold one): listed
  // as active in every diagnostics_t.
  void add_start_alarm(const std::string& kind, const std::string& source, const std::string& text);

  [[nodiscard]] BridgeCounters counters() const;
  // What describe publishes (empty before attach()).
  [[nodiscard]] softplc_hmi::cell_description_t description();
  [[nodiscard]] const Channels& channels() const { return ch_; }
  // Our LCM transport (transport.hpp): its counters, and in tests (memq://)
  // the subscriptions that see what the bridge publishes.
  [[nodiscard]] Transport& transport() { return *transport_; }

  // Decodes and serves one command message (the handler; the fuzz target
  // feeds it raw bytes). Never throws.
  void on_command_bytes(const void* data, std::size_t size);

 private:
  struct Layout;  // what attach() resolved for one runtime
  struct DeviceSeen;
  void run();
  void flush_replies();
  template <class F>
  void with_runtime(F f);  // f(runtime) between the debugger's commands, or not at all
  int publish_values(bool full);
  softplc_hmi::reply_t serve(const softplc_hmi::command_t& c);
  std::string refusal(const softplc_hmi::command_t& c) const;
  bool may(const std::vector<Item<std::string>>& patterns, const std::string& name) const;

  HmiConfig cfg_;
  std::string cell_file_;
  Channels ch_;
  std::optional<Key> key_;
  ReplayGuard replay_;
  std::unique_ptr<Transport> transport_;
  Transport::Subscription* sub_ = nullptr;
  debug::Debugger* dbg_ = nullptr;
  std::mutex layout_mu_;            // attach() against the bridge's thread
  std::shared_ptr<Layout> layout_;  // observers keep theirs alive
  std::thread thread_;
  bool in_handler_ = false;                    // inside the transport's dispatch (its thread)
  std::vector<softplc_hmi::reply_t> pending_;  // replies to publish after it
  std::atomic<bool> stop_{false};
  mutable std::mutex counters_mu_;
  BridgeCounters counters_;
  std::vector<softplc_hmi::alarm_t> start_alarms_;  // under counters_mu_
  std::chrono::steady_clock::time_point last_full_{};
};

}  // namespace plc::hmi

// plcrun's side of the HMI (hmi-bridge/README.md, "Process layout"): the
// shared memory for the bridge process (plchmi), the scan-end copies into
// it, the commands that come back through it, served by the debugger core,
// and the supervision of plchmi. Nothing here reads the network or parses
// text from it: a command is a binary record that host_commands.hpp checks
// field by field before the debugger sees it.
//
// Threads: the scan threads only copy published values into their slot
// when the bridge asks (one atomic load per scan otherwise, ScanSnapshot).
// Everything else runs on the host's own thread (start()), or on the
// caller's thread in lockstep (round(): tests in virtual time drive both
// halves from one thread). Commands take the debugger's session mutex
// with a bounded try-lock and answer "busy" rather than wait behind the
// console; a scan never waits for the host, and the host never for plchmi.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "plc/cell_config.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/hmi/host_commands.hpp"
#include "plc/hmi/host_privileges.hpp"
#include "plc/hmi/ipc/regions.hpp"
#include "plc/hmi/scan_snapshot.hpp"
#include "plc/hmi/supervisor.hpp"

namespace plc::hmi {

class Host {
 public:
  enum class Mode {
    Lockstep,    // no thread, no process: the caller runs round() (tests)
    Thread,      // the host's thread; the bridge runs in this process (tests, benchmarks)
    Supervised,  // the host's thread, and plchmi started and restarted by it (plcrun)
  };
  struct Options {
    Mode mode = Mode::Supervised;
    std::string plchmi;  // the executable ("": beside /proc/self/exe)
    Supervisor::Backoff backoff;
    // Where the host's log lines go (default: stderr, "plcrun: hmi: ...").
    std::function<void(const std::string&)> log;
  };

  // Loads the key file, resolves the bridge's user and network namespace.
  // Throws ConfigError (file:line:col) when one cannot be used.
  Host(const HmiConfig& cfg, std::string cell_file, Options options);
  ~Host();
  Host(const Host&) = delete;
  Host& operator=(const Host&) = delete;

  // Before the runtime's first scan (debug::Debugger::Options::on_build),
  // and again after every rebuild (goto, restart): resolves the patterns
  // (ConfigError for one that matches no variable), writes the cell layout
  // into the shared memory and adds the scan observers.
  void attach(Runtime& rt);
  // An alarm that holds for the whole run (kind `retain_cold_start`: a warm
  // start that fell back to a cold one), listed as active in every
  // diagnostics_t the bridge publishes. Noted before the attach() that
  // should carry it (plcrun: in the first build, before the first scan).
  void add_start_alarm(const std::string& kind, const std::string& source, const std::string& text);
  // Commands are served through this debugger (none: refused, NoDebugger).
  void set_debugger(debug::Debugger* d) { dbg_ = d; }

  // Thread and Supervised: the host's thread (and plchmi). After attach().
  void start();
  // plchmi told to stop (SIGTERM, then SIGKILL after a grace time) and
  // reaped; the thread joined. Idempotent; never throws.
  void stop();

  // One round on the caller's thread: serves the waiting commands (at most
  // a ring's worth), refreshes statistics, diagnostics and device notes.
  // Returns the commands served.
  int round();

  // The regions (after the first attach()); a bridge in this process maps
  // them with regions().view().
  [[nodiscard]] ipc::Regions& regions() { return *regions_; }
  [[nodiscard]] bool attached() const { return regions_ != nullptr; }
  // The doorbell plchmi rings after it queued commands (an eventfd).
  [[nodiscard]] int doorbell() const { return doorbell_; }
  // Supervised: plchmi's pid now (0 while it is down).
  [[nodiscard]] int bridge_pid() const;
  // Lines for plcrun's summary: outages, the bridge's counters.
  [[nodiscard]] std::vector<std::string> summary() const;
  // Called when a rebuild needs new regions (a layout that no longer fits
  // them): an in-process bridge must attach again.
  void on_new_regions(std::function<void()> f) { new_regions_ = std::move(f); }

 private:
  struct Layout;
  void run();
  void serve(const ipc::CommandRecord& rec, const Layout& l, ipc::ReplyRecord& reply);
  void execute(const HostCommand& c, const Layout& l, ipc::ReplyRecord& reply);
  void refresh_notes(const Layout& l);
  // f(runtime) when it may be read now (between the debugger's commands).
  template <class F>
  bool with_runtime(const Layout& l, F f);
  void make_supervisor();
  void supervise(std::chrono::steady_clock::time_point now);
  void note_outage(const std::string& cause, std::int64_t down_utime);
  void write_outages();  // outages_mu_ held (or before the thread)
  [[nodiscard]] std::string name_of(const Layout& l, const HostTarget& t) const;
  void log(const std::string& line) const;

  HmiConfig cfg_;
  std::string cell_file_;
  Options opt_;
  Privileges privileges_;
  ipc::Settings settings_;
  std::uint64_t boot_epoch_ = 0;
  std::shared_ptr<ipc::Regions> regions_;
  debug::Debugger* dbg_ = nullptr;
  mutable std::mutex layout_mu_;    // attach() against the host's thread
  std::shared_ptr<Layout> layout_;  // the scan observers keep theirs alive
  std::function<void()> new_regions_;
  std::vector<ipc::CellLayout::Alarm> start_alarms_;  // attach()'s thread
  int doorbell_ = -1;
  std::unique_ptr<Supervisor> supervisor_;
  std::atomic<bool> restart_bridge_{false};  // new regions: plchmi starts again on them
  std::thread thread_;
  std::atomic<bool> stop_{false};
  // The host's thread (or round()'s caller) only: one record each, reused.
  std::unique_ptr<ipc::CommandRecord> rec_;
  std::unique_ptr<ipc::ReplyRecord> reply_;
  mutable std::mutex outages_mu_;
  ipc::OutageNote outages_;
  std::int64_t down_total_us_ = 0;  // the sum of up - down over the outages
  std::chrono::steady_clock::time_point next_notes_{};
};

}  // namespace plc::hmi

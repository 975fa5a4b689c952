// The HMI bridge: the LCM side of the HMI, in its own process (plchmi,
// hmi-bridge/README.md "Process layout"). It publishes what plcrun puts in
// the shared memory (values, statistics, diagnostics, the cell layout) and
// turns LCM commands into binary records for plcrun: the decode guard, the
// shared key, the access patterns (as plcrun resolved them into the
// layout), IEC literals parsed into the type's bytes and breakpoint
// conditions compiled into code all happen here. It links no runtime and
// no plugin; it reads the shared memory and writes only the control region.
//
// Threads: one. LCM's handle and publish, the rings and the snapshot
// requests on the bridge's thread (run()), or on the caller's thread when
// a test drives service() itself; in lockstep (set_peer) service() also
// runs plcrun's host round in between, so that a test in virtual time
// drives both halves deterministically from one thread.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "plc/hmi/channels.hpp"
#include "plc/hmi/command_auth.hpp"
#include "plc/hmi/ipc/notes.hpp"
#include "plc/hmi/ipc/regions.hpp"
#include "plc/hmi/pattern.hpp"
#include "plc/hmi/transport.hpp"
#include "softplc_hmi/alarm_t.hpp"
#include "softplc_hmi/cell_description_t.hpp"
#include "softplc_hmi/command_t.hpp"
#include "softplc_hmi/diagnostics_t.hpp"
#include "softplc_hmi/reply_t.hpp"
#include "softplc_hmi/stats_t.hpp"
#include "softplc_hmi/trace_sample_t.hpp"
#include "softplc_hmi/values_t.hpp"

namespace plc::hmi {

struct BridgeCounters {
  std::uint64_t published = 0;  // values_t messages sent
  std::uint64_t dropped = 0;    // publish ticks missed because the bridge was late
  std::uint64_t commands = 0;   // commands applied
  std::uint64_t refused = 0;    // refused: access, unknown verb, plcrun or the debugger said no
  std::uint64_t bad_tag = 0;    // HMAC did not verify (or missing with a key)
  std::uint64_t replayed = 0;   // counter not above the client's last one
  std::uint64_t stale = 0;      // signed for another epoch (a capture from before a restart)
  std::uint64_t malformed = 0;  // did not decode as a command_t
};

// Sees every message the bridge publishes, as it publishes it, on the
// bridge's thread (the web server, web/web_server.hpp). It must return
// quickly: it copies what it needs and hands it to its own thread.
class BridgeTap {
 public:
  virtual ~BridgeTap() = default;
  virtual void on_description(const softplc_hmi::cell_description_t&) {}
  virtual void on_values(const softplc_hmi::values_t&, const softplc_hmi::trace_sample_t&) {}
  virtual void on_stats(const softplc_hmi::stats_t&) {}
  virtual void on_diagnostics(const softplc_hmi::diagnostics_t&) {}
  virtual void on_alarm(const softplc_hmi::alarm_t&) {}
  virtual void on_reply(const softplc_hmi::reply_t&) {}
};

class Bridge {
 public:
  // Commands that another thread of this process hands in (submit()),
  // waiting for the bridge's next round.
  static constexpr std::size_t kLocalInbox = 64;

  // `regions`: plcrun's shared memory as this process maps it; `doorbell`:
  // the eventfd to ring after queueing commands (-1: none, lockstep).
  // Throws std::runtime_error (file:line:col: ...) when LCM cannot open the
  // url, or the shared memory holds no usable cell layout.
  explicit Bridge(std::unique_ptr<ipc::Regions> regions, int doorbell = -1);
  ~Bridge();
  Bridge(const Bridge&) = delete;
  Bridge& operator=(const Bridge&) = delete;

  // Lockstep: plcrun's host round, run inside service() and before the
  // bridge reads statistics or diagnostics.
  void set_peer(std::function<void()> host_round) { peer_ = std::move(host_round); }
  // New regions from plcrun (a rebuild of another shape), in this process.
  void attach(std::unique_ptr<ipc::Regions> regions);

  // The bridge's thread (in this process: tests, benchmarks; plchmi runs
  // run() on its main thread).
  void start();
  void stop();
  // Until `stop` is set: requests and publishes at the configured rate
  // (each snapshot as soon as the next scan end has filled it), serves
  // commands, statistics and diagnostics at 1 Hz.
  void run(const std::atomic<bool>& stop);

  // One round on the caller's thread (tests, virtual time): handles every
  // command waiting (up to a bound), lets plcrun serve them (lockstep),
  // publishes the replies, the snapshots the scans have filled since the
  // last round, an alarm for each device state change and outage since
  // then, and asks for the next snapshots. Returns the values_t messages sent.
  int service(int wait_ms = 0);
  void publish_stats();
  void publish_diagnostics();
  void publish_description();
  // Publishes an alarm_t on PREFIX_ALARM for every device whose state, as
  // its task's scans saw it, changed since the last call (lost, back), and
  // for every outage of the bridge that plcrun noted and none announced
  // yet. Returns how many.
  int publish_device_alarms();

  [[nodiscard]] BridgeCounters counters() const;
  // What describe publishes, signed with a key.
  [[nodiscard]] softplc_hmi::cell_description_t description();
  // This bridge's boot epoch (command_auth.hpp): made when it is
  // constructed, kept over rebuilds of the runtime (goto, restart).
  [[nodiscard]] const Epoch& epoch() const { return epoch_; }
  [[nodiscard]] const Channels& channels() const { return ch_; }
  // Our LCM transport (transport.hpp): its counters, and in tests (memq://)
  // the subscriptions that see what the bridge publishes.
  [[nodiscard]] Transport& transport() { return *transport_; }

  // The tap (nullptr: none); set before start()/run().
  void set_tap(BridgeTap* tap) { tap_ = tap; }
  // A command from this process (the web server, which authenticated its
  // session itself): served at the bridge's next round exactly as an LCM
  // command (the same patterns, stop_commands, plcrun's checks) except for
  // the shared key's tag, and answered through the tap's on_reply (and on
  // PREFIX_REPLY). Any thread. False when kLocalInbox commands are waiting.
  bool submit(softplc_hmi::command_t c);

  // Decodes and serves one command message (the handler; the fuzz target
  // feeds it raw bytes). Never throws.
  void on_command_bytes(const void* data, std::size_t size);

 private:
  struct View;
  struct Pending;
  using Clock = std::chrono::steady_clock;
  void sync();                       // the peer's round (lockstep)
  bool load_view(std::string& err);  // the layout of the current generation
  void check_generation();
  int poll_fills();
  void tick(Clock::time_point now);
  int publish_slot(std::size_t s);
  void drain_replies();
  void expire_pending(Clock::time_point now);
  void flush_replies();
  void publish_reply(softplc_hmi::reply_t r);
  // The command (decoded, authenticated): a reply now, or nullopt when it
  // went to plcrun and its reply comes through the ring.
  // `local`: from submit(), authenticated by its caller.
  std::optional<softplc_hmi::reply_t> handle(const softplc_hmi::command_t& c, bool local = false);
  void serve_local();
  std::optional<softplc_hmi::reply_t> queue(ipc::CommandRecord& rec, Pending p);
  void count(std::uint64_t BridgeCounters::*counter, std::uint64_t n = 1);
  [[nodiscard]] bool fast_poll(Clock::time_point now) const;
  // The key's checks of a command that changes something: "" when it
  // passes (no key: always), else the refusal, counted.
  std::string authenticate(const softplc_hmi::command_t& c);
  // What a tag binds on `channel` (the cell's name from the layout).
  [[nodiscard]] TagContext tag_context(const std::string& channel) const;

  std::unique_ptr<ipc::Regions> regions_;
  ipc::Settings settings_;
  std::string where_;  // "cell.yaml" for messages
  Channels ch_;
  std::optional<Key> key_;
  // This process's boot epoch (command_auth.hpp): a plchmi started again
  // has a new one, and with it an empty replay guard.
  Epoch epoch_;
  ReplayGuard replay_;  // counters within epoch_: both live as long as the bridge
  std::unique_ptr<Transport> transport_;
  Transport::Subscription* sub_ = nullptr;
  int doorbell_ = -1;
  std::function<void()> peer_;
  std::unique_ptr<View> view_;
  std::map<std::uint32_t, Pending> pending_;  // token -> the command waiting for plcrun
  std::uint32_t next_token_ = 1;
  std::unique_ptr<ipc::CommandRecord> rec_;    // reused
  std::unique_ptr<ipc::ReplyRecord> reply_;    // reused
  bool in_handler_ = false;                    // inside the transport's dispatch
  std::vector<softplc_hmi::reply_t> replies_;  // to publish after it
  BridgeTap* tap_ = nullptr;
  std::mutex local_mu_;
  std::vector<softplc_hmi::command_t> local_;  // submit()'s inbox
  std::thread thread_;
  std::atomic<bool> stop_{false};
  mutable std::mutex counters_mu_;
  BridgeCounters counters_;
};

}  // namespace plc::hmi

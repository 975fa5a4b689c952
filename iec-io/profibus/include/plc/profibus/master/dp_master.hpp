// The DP master class 1 (DP-V0) without threads or a clock of its own: the
// profibus plugin calls tick() from its real-time thread, or from step() in
// virtual time; tests call it directly.
//
// A single master holds the token all the time: each bus cycle it runs one
// message cycle per slave, then any Global_Control, then passes the token
// to itself (SD4 TS->TS). Every `gap_factor` rotations it asks one address
// of its GAP (TS+1 .. HSA, then 0 .. TS-1, skipping its slaves) for its FDL
// status: the GAP update a multi-master ring needs; here an answering
// master is only reported (no ring is built).
//
// Per slave (EN 50170 vol. 2, DP master state machine):
//   Slave_Diag -> Set_Prm (WD, minTSDR, Ident_Number, group, user
//   parameters from the GSD) -> Chk_Cfg (the configured modules' Cfg
//   bytes) -> Slave_Diag until ready -> Data_Exchange every cycle.
// A diagnosis with Prm_Fault, Cfg_Fault, Not_Supported or Prm_Req starts
// again at Set_Prm (after `retry` when it was a fault); Master_Lock
// (another master owns the slave) or a foreign Ident_Number waits `retry`.
// An implausible answer (a Data_Exchange answer of another size than
// configured, a Slave_Diag answer without a diagnosis) is a fault with
// Invalid_Slave_Response, the master's own diagnosis bit. An answer DH (high
// priority) to Data_Exchange makes the next cycle read the diagnosis; RS
// (the slave lost its parameters, e.g. its watchdog) starts it up again.
// No answer within the slot time: the request is repeated up to max_retry
// times with the same FCB, then the slave is lost (Station_Non_Existent):
// its inputs read 0, its link is Offline, and after `retry` it is
// parametrised again by itself.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plc/io/device_link.hpp"
#include "plc/profibus/dp/services.hpp"
#include "plc/profibus/fdl/deframer.hpp"
#include "plc/profibus/fdl/timing.hpp"
#include "plc/profibus/link/capture.hpp"
#include "plc/profibus/link/line.hpp"
#include "plc/types.hpp"

namespace plc::profibus::master {

struct SlaveEntry {
  std::string name;
  std::uint8_t address = 3;
  dp::SetPrm prm;                 // ident, watchdog, group, user parameters, Freeze/Sync requests
  std::vector<std::uint8_t> cfg;  // Chk_Cfg
  std::size_t input_bytes = 0, output_bytes = 0;
  // false: configured but taken out of the cycle (a station not yet
  // fitted): never called, Offline, its diagnosis Deactivated
  // (Station_Status_2 bit 7, the master's own bit).
  bool active = true;
};

struct MasterConfig {
  std::uint8_t address = 1;
  fdl::BusParameters bus;
  // How long to wait for an answer: TSL in bit times at the baud rate, but
  // at least this (a pty or a USB adapter answers in milliseconds, not in
  // bit times; README: what a PC can meet).
  TIME min_reply_timeout{0};
  TIME cycle = std::chrono::milliseconds(5);  // bus cycle (Min_Slave_Intervall of the slaves)
  TIME retry = std::chrono::seconds(1);       // before a lost or faulty slave is started again
  bool token = true;                          // send the token to itself every cycle
};

enum class SlaveState : std::uint8_t {
  Waiting,   // lost or faulty: started again at next_try
  Starting,  // Slave_Diag, Set_Prm, Chk_Cfg, Slave_Diag
  Online,    // Data_Exchange
  Fault,     // Prm_Fault, Cfg_Fault, Not_Supported, Invalid_Slave_Response, a foreign
             // Ident_Number, Master_Lock (waits retry)
};
const char* to_string(SlaveState s);

struct SlaveCounters {
  std::uint64_t data_exchanges = 0, retries = 0, losses = 0, startups = 0, diag_reads = 0,
                prm_faults = 0, cfg_faults = 0, wrong_size = 0, refused = 0;
};

struct MasterCounters {
  std::uint64_t cycles = 0, tokens = 0, gap_requests = 0, global_controls = 0, bad_bytes = 0,
                unexpected = 0;
  // Answers dropped in the quiet time after a repeated request (the
  // slave's answer to a request the master had already had answered).
  std::uint64_t late_answers = 0;
};

class DpMaster {
 public:
  DpMaster(const MasterConfig& cfg, link::Line* line);
  void attach(link::Line* line) { line_ = line; }
  // New settings before the first tick (the plugin computes the bus
  // parameters once every slave is known).
  void configure(const MasterConfig& cfg);
  void set_capture(link::Capture* c) { capture_ = c; }
  std::size_t add(const SlaveEntry& e);

  // Reads the line, handles answers and time-outs, and sends what is due.
  void tick(TIME now);
  // Whether a request is waiting for its answer.
  [[nodiscard]] bool awaiting() const { return pending_.kind != Kind::None; }
  [[nodiscard]] std::uint64_t telegrams_sent() const { return sent_; }

  // Queues Global_Control for the next cycle (groups: Group_Select, 0 = all).
  void global_control(std::uint8_t command, std::uint8_t groups);

  // Cyclic data (callers synchronise: the plugin holds its mutex).
  std::span<const std::uint8_t> inputs(std::size_t d) const { return slaves_[d]->in; }
  std::span<std::uint8_t> outputs(std::size_t d) { return slaves_[d]->out; }
  io::DeviceLink& link(std::size_t d) { return slaves_[d]->link; }
  [[nodiscard]] SlaveState state(std::size_t d) const { return slaves_[d]->state; }
  [[nodiscard]] const SlaveCounters& counters(std::size_t d) const { return slaves_[d]->counters; }
  [[nodiscard]] const MasterCounters& counters() const { return counters_; }
  [[nodiscard]] const dp::Diagnosis& last_diagnosis(std::size_t d) const {
    return slaves_[d]->diag;
  }
  [[nodiscard]] std::string diagnostics(std::size_t d) const;
  [[nodiscard]] std::size_t size() const { return slaves_.size(); }
  [[nodiscard]] TIME reply_timeout() const { return reply_timeout_; }
  // The last completed bus cycle (first request to the token), measured on
  // the master's clock.
  [[nodiscard]] TIME last_cycle_time() const { return last_cycle_; }
  // Called on every change of a slave's state (the plugin logs them).
  std::function<void(std::size_t slave, SlaveState state, const std::string& why)> on_change;
  // Called when another master answers the GAP update.
  std::function<void(std::uint8_t address)> on_other_master;

 private:
  enum class Kind : std::uint8_t { None, Diag, SetPrm, ChkCfg, DataExchange, FdlStatus };
  enum class Step : std::uint8_t { Diag1, SetPrm, ChkCfg, Diag2, Exchange };
  struct Slave {
    SlaveEntry cfg;
    SlaveState state = SlaveState::Waiting;
    Step step = Step::Diag1;
    std::vector<std::uint8_t> in, out;
    io::DeviceLink link;
    SlaveCounters counters;
    dp::Diagnosis diag;
    bool diag_known = false;
    bool read_diag = false;  // DH seen: read the diagnosis next cycle
    int not_ready = 0;       // diagnosis reads without "ready"
    TIME next_try{0};
    int fcb = -1;  // -1: next request FCB=1 FCV=0
    std::string last_error;
  };
  struct Pending {
    Kind kind = Kind::None;
    std::size_t slave = 0;
    std::uint8_t da = 0;
    int retries = 0;
    TIME deadline{0};
    TIME first_sent{0}, last_sent{0};  // the request, and its last repetition
    std::array<std::uint8_t, fdl::kMaxTelegram> bytes{};
    std::size_t length = 0;
  };

  void send(const fdl::Telegram& t, TIME now);
  void request(Kind k, std::size_t slave, fdl::Telegram t, TIME now);
  void on_answer(const fdl::Telegram& t, TIME now);
  void on_timeout(TIME now);
  bool next_transaction(TIME now);
  void start_slave(Slave& s, TIME now);
  void lose(Slave& s, TIME now, const std::string& why);
  void fault(Slave& s, TIME now, const std::string& why);
  void online(Slave& s);
  void changed(const Slave& s);
  void post_diagnosis(Slave& s, const dp::Diagnosis& d);
  void post_invalid_response(Slave& s);
  void handle_diag(Slave& s, const dp::Diagnosis& d, TIME now);

  MasterConfig cfg_;
  link::Line* line_;
  link::Capture* capture_ = nullptr;
  fdl::Deframer rx_;
  std::vector<std::unique_ptr<Slave>> slaves_;
  Pending pending_;
  TIME reply_timeout_{0};
  // After an answer to a repeated request, nothing is sent before this:
  // the slave may still answer the repetition, and on a line with latency
  // (a pty, a USB adapter) that answer would otherwise be taken for the
  // answer to the next request, which is then one exchange stale.
  TIME quiet_until_{-1};       // -1: none yet
  std::uint8_t quiet_da_ = 0;  // the station whose late answer is dropped
  // The cycle: next slave to serve, then Global_Control, token, GAP.
  std::size_t cursor_ = 0;
  bool in_cycle_ = false;
  TIME cycle_start_{0}, next_cycle_{0}, last_cycle_{0};
  std::uint8_t gc_command_ = 0, gc_groups_ = 0;
  bool gc_pending_ = false;
  std::uint32_t rotations_ = 0;
  std::uint8_t gap_next_ = 0;
  std::uint64_t sent_ = 0;
  MasterCounters counters_;
  std::array<std::uint8_t, fdl::kMaxTelegram> tx_{};
};

}  // namespace plc::profibus::master

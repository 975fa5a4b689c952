// A DP-V0 slave (EN 50170 vol. 2, DP slave state machine) in front of a
// simulated device (any registered plc::io::DeviceModel), without threads
// or a clock of its own: dpslavesim calls tick() in real time, the
// profibus plugin's simulate mode and the tests call it in virtual time.
//
//   Wait_Prm --Set_Prm ok--> Wait_Cfg --Chk_Cfg ok--> Data_Exch
//   Set_Prm with a wrong Ident_Number, user parameter length or an
//     unsupported Freeze/Sync request: Prm_Fault, stays in Wait_Prm;
//   Chk_Cfg that is not the slave's configuration: Cfg_Fault, back to
//     Wait_Prm (a real slave wants new parameters after a Cfg_Fault);
//   watchdog (Set_Prm WD_On, 10 ms x WD_Fact_1 x WD_Fact_2) without a
//     telegram from its master: back to Wait_Prm, outputs cleared, the lock
//     released (Prm_Req in the next diagnosis).
// Data_Exchange outside Data_Exch, or from another master, is answered RS
// (no service activated); Set_Prm of another master while locked is
// acknowledged and ignored (Master_Lock in that master's diagnosis).
// Global_Control (SDN to 127 or to the slave, its master only, for its
// group): Clear_Data, Freeze/Unfreeze (inputs held at the Freeze), Sync/
// Unsync (outputs applied only at the next Sync); Freeze or Sync without
// the Set_Prm request sets Not_Supported. A repeated request (FCV set, FCB
// as last time) gets the last answer again without being executed twice.
// The model sees its window at the start of the slave's I/O: the first
// model->input_size() input bytes, model->output_size() output bytes; the
// rest of the configured I/O reads 0 and is ignored.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "plc/io/device_model.hpp"
#include "plc/profibus/fdl/deframer.hpp"
#include "plc/profibus/link/line.hpp"
#include "plc/types.hpp"

namespace plc::profibus::slave {

struct SlaveConfig {
  std::uint8_t address = 3;
  std::uint16_t ident = 0;
  std::size_t input_bytes = 0, output_bytes = 0;
  // Chk_Cfg: with `modules` (the GSD's Cfg bytes of its modules, each one
  // byte here) any combination of at most `max_modules` of them whose sizes
  // add up to the I/O above is accepted (a modular station); without, the
  // configuration must be exactly `cfg`.
  std::vector<std::uint8_t> modules;
  std::size_t max_modules = 1;
  std::vector<std::uint8_t> cfg;
  std::size_t user_prm_len = 0;
  // The GSD's Max_Diag_Data_Len (6..244): extended diagnosis that does not
  // fit is cut at that length and Ext_Diag_Overflow set.
  std::size_t max_diag_len = 244;
  bool freeze_supported = true, sync_supported = true;
};

struct SlaveFaults {
  bool silent = false;            // answers nothing (a pulled plug)
  bool stat_diag = false;         // Stat_Diag: the master keeps reading diagnosis
  std::vector<std::uint8_t> ext;  // extended diagnosis blocks (Ext_Diag)
  bool ignore_watchdog = false;   // a slave whose watchdog never fires
};

enum class SlaveState : std::uint8_t { WaitPrm, WaitCfg, DataExch };
const char* to_string(SlaveState s);

struct SlaveCounters {
  std::uint64_t requests = 0, data_exchanges = 0, diag_reads = 0, set_prm = 0, prm_faults = 0,
                chk_cfg = 0, cfg_faults = 0, global_controls = 0, watchdog_expiries = 0,
                repeats = 0, refused = 0, bad_bytes = 0;
};

class DpSlave {
 public:
  DpSlave(const SlaveConfig& cfg, std::unique_ptr<io::DeviceModel> model, link::Line& line);

  // Reads the line, answers, steps the model, runs the watchdog.
  void tick(TIME now);

  [[nodiscard]] SlaveState state() const { return state_; }
  [[nodiscard]] std::uint8_t address() const { return cfg_.address; }
  [[nodiscard]] std::uint8_t master() const { return master_; }
  [[nodiscard]] bool frozen() const { return freeze_; }
  [[nodiscard]] bool synced() const { return sync_; }
  [[nodiscard]] const SlaveCounters& counters() const { return counters_; }
  [[nodiscard]] std::span<const std::uint8_t> applied_outputs() const { return applied_; }
  SlaveFaults& faults() { return faults_; }
  io::DeviceModel& model() { return *model_; }
  [[nodiscard]] std::string describe() const;

 private:
  void on_request(const fdl::Telegram& t, TIME now);
  void answer(const fdl::Telegram& t);
  void answer_sc();
  void refuse(const fdl::Telegram& req, std::uint8_t function);
  void reply_data(const fdl::Telegram& req, std::int16_t dsap, std::int16_t ssap,
                  std::uint8_t function, std::span<const std::uint8_t> data);
  void set_prm(const fdl::Telegram& t, TIME now);
  void chk_cfg(const fdl::Telegram& t);
  void global_control(const fdl::Telegram& t);
  void data_exchange(const fdl::Telegram& t);
  void to_wait_prm();
  [[nodiscard]] bool cfg_ok(std::span<const std::uint8_t> cfg) const;
  [[nodiscard]] std::vector<std::uint8_t> diagnosis(std::uint8_t asking) const;

  SlaveConfig cfg_;
  std::unique_ptr<io::DeviceModel> model_;
  link::Line& line_;
  fdl::Deframer rx_;
  SlaveState state_ = SlaveState::WaitPrm;
  SlaveFaults faults_;
  SlaveCounters counters_;
  std::uint8_t master_ = 0xFF;
  std::uint8_t group_ = 0;
  std::uint32_t watchdog_ms_ = 0;
  bool freeze_enabled_ = false, sync_enabled_ = false;
  bool freeze_ = false, sync_ = false;
  bool prm_fault_ = false, cfg_fault_ = false, not_supported_ = false;
  bool diag_changed_ = false;
  std::vector<std::uint8_t> accepted_cfg_;
  std::vector<std::uint8_t> inputs_, frozen_inputs_, outputs_, applied_;
  std::vector<std::uint8_t> model_in_, model_out_;
  TIME last_master_{0};
  TIME last_step_{0};
  bool stepped_ = false;
  int last_fcb_ = -1;
  std::array<std::uint8_t, fdl::kMaxTelegram> last_answer_{};
  std::size_t last_answer_len_ = 0;
};

}  // namespace plc::profibus::slave

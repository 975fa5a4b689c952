// Simulated Sartorius PR5510 with a PR1721/31 (Profibus-DP) or PR1721/34
// (DeviceNet) card: the device side of the 8-byte read and write windows
// (spec shared/specs/sartorius-pr1721.md §3-§5, implementation notes §7.1)
// on top of a filling process (filling_process.hpp).
//
// Every 20 ms (the PR5510 cycle, spec §0) the model samples the write
// window and refreshes the read window; between cycles the read window is
// frozen, as on the real device. Outputs 1/2/3 (W[6]) drive the coarse,
// fine and discharge valves of the simulated hopper.
//
// Choices where the spec is open (each marked [INFERRED] there):
//  * unknown/reserved read codes are echoed with value 0 (strict_codes:
//    not echoed, so the master times out);
//  * write codes outside the manual's tables are acknowledged with
//    Write_Active together with Cmd_Error; a failed command also sets
//    Write_Active, so the handshake always finishes; Cmd_Error is cleared
//    when the next command is accepted;
//  * Write_Value is ignored for the firmware commands 0x70..0x75;
//  * application codes (read 0x18..0xC7, write 0x18..0x39 and 0x78..0xC7)
//    form one register bank: a written DINT reads back on the same code.
//    Write codes 0x18/0x19/0x1A are "Limit1/2/3 On" (the manual's example):
//    Limit n turns on while the net weight is at or above that value;
//  * analog test: the weight shows test_value while Test Active;
//  * the tare and the zero need standstill within tare_timeout, else
//    error 31; Dimmed = Above FSD or Below Zero;
//  * calibration is done at the indicator's front panel (the windows have
//    no calibration command); the panel_* calls below stand for the
//    operator's keys and produce the calibration errors of §5.3: 40 when the
//    CAL switch is locked, 41 for a calibration key outside calibration
//    mode, 42 for a window zero/tare command while calibration is in
//    progress, 46 when calibration is started while a tare/zero waits.
//    Finishing a calibration sets Cal Changed (§3.4 R[5].1).
#pragma once

#include <array>
#include <cstdint>

#include "plc/fb/weighing/window_codec.hpp"
#include "plc/io/device_model.hpp"
#include "pr5510/filling_process.hpp"

namespace plc::sim {

struct Pr5510Config {
  weighing::Bus bus = weighing::Bus::Profibus;
  weighing::PackedOrder packed_order = weighing::PackedOrder::MsbFirst;
  double full_scale = 50.0;   // kg (FSD)
  std::uint8_t decimals = 2;  // display digits: 0.01 kg
  std::uint8_t division = 1;  // d in digits
  weighing::Unit unit = weighing::Unit::kg;
  double overload = 5.0;                                  // kg above FSD before Over-load
  double zero_range = 1.0;                                // kg either side of the calibration zero
  double standstill_range = 2.0;                          // digits (within +- this ...)
  TIME standstill_time = std::chrono::milliseconds(300);  // ... for this long
  TIME filter_time = std::chrono::milliseconds(40);       // digital filter time constant
  TIME tare_timeout = std::chrono::seconds(3);            // standstill wait, then error 31
  bool legal_for_trade = false;    // W&M: tare of a negative weight is error 33
  bool cal_switch_locked = false;  // the sealed CAL switch: panel calibration is error 40
  double test_value = 5.0;         // kg shown during the analog test
  bool strict_codes = false;
  bool scale_interface = true;  // "disable" = no data communication
  std::uint16_t model = 0x5510;
  std::uint16_t version = 0x0312;  // Rel 3.12, BCD like the model ([INFERRED])
  FillingConfig filling{};
};

// Parses `params:` of the cell config (keys listed in the README).
Pr5510Config pr5510_config_from(const io::ModelParams& p);

class Pr5510Model final : public io::DeviceModel {
 public:
  explicit Pr5510Model(const Pr5510Config& c);
  explicit Pr5510Model(const io::ModelParams& p) : Pr5510Model(pr5510_config_from(p)) {}

  [[nodiscard]] std::size_t input_size() const override { return weighing::kWindowSize; }
  [[nodiscard]] std::size_t output_size() const override { return weighing::kWindowSize; }
  void step(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
            std::span<std::uint8_t> to_plc) override;
  void power_cycle() override;
  // The host's I/O connection timed out (a DeviceNet slave's expected
  // packet rate, a PROFINET AR's watchdog): outputs 1-3 off, the valves
  // closed, until the next I/O message (step_io with new_message, or
  // step(): a host that calls it delivers the outputs every cycle). The
  // manual says nothing of a fieldbus loss (spec §2.5, §2.6 show only the
  // "connection timeout" LED) [INFERRED]: a dosing output left as last
  // commanded while no master watches it overfills the hopper, and every
  // later batch then fails with "weight invalid" (16#8204); the card's
  // outputs go to their defined idle state of 0, as a PROFINET device's do
  // (IOPS bad: substitute value 0) and as the DeviceNet idle/fault action of
  // a polled connection that timed out.
  void io_connection_lost() override;
  void step_io(TIME now, TIME dt, std::span<const std::uint8_t> from_plc, bool new_message,
               std::span<std::uint8_t> to_plc) override;
  [[nodiscard]] bool master_lost() const { return master_lost_; }

  // ---- inspection and fault injection (tests) ----
  FillingProcess& process() { return process_; }
  [[nodiscard]] const Pr5510Config& config() const { return cfg_; }
  [[nodiscard]] DINT gross_digits() const { return gross_; }
  [[nodiscard]] DINT net_digits() const { return gross_ - tare_; }
  [[nodiscard]] DINT tare_digits() const { return tare_; }
  [[nodiscard]] DINT fsd_digits() const { return fsd_digits_; }
  [[nodiscard]] const weighing::StatusBits& status() const { return st_; }
  [[nodiscard]] std::uint8_t last_error() const { return last_error_; }
  [[nodiscard]] std::uint64_t cycles() const { return cycles_; }
  [[nodiscard]] std::uint64_t commands_accepted() const { return commands_accepted_; }
  void set_adu_error(bool on) { adu_error_ = on; }
  // Fault injection "stop answering": the host reports the device Offline.
  void set_answering(bool on) { set_answering_now(on); }
  void set_input(int n, bool on);  // digital inputs 1..3

  // ---- the front panel: calibration by an operator (see the header) ----
  // Enter calibration mode; false (with error 40 or 46) if refused.
  bool panel_start_calibration();
  // Calibration keys: take the present load as the new zero, or as
  // `known_kg` (the span). False with error 41 outside calibration mode.
  bool panel_calibrate_zero();
  bool panel_calibrate_span(double known_kg);
  // Leave calibration mode, keeping the new calibration (Cal Changed).
  bool panel_finish_calibration();
  [[nodiscard]] bool calibrating() const { return calibrating_; }

 private:
  enum class Pending : std::uint8_t { None, Zero, Tare };

  [[gnu::noinline]] void tick_1ms();
  [[gnu::noinline]] void filter_drawn();
  [[gnu::noinline]] void step_other(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
                                    std::span<std::uint8_t> to_plc);
  [[gnu::noinline]] void step_with_cycle(std::span<const std::uint8_t> from_plc,
                                         std::span<std::uint8_t> to_plc);
  // The read window to the master (zeros without the scale interface).
  [[gnu::always_inline]] inline void put_read_window(std::span<std::uint8_t> to_plc) const;
  void device_cycle(std::span<const std::uint8_t> w);
  void update_weight_and_status();
  void serve_read(std::uint8_t code);
  void accept_write(std::uint8_t code, std::uint32_t raw);
  // Starts a firmware command; returns false if it finished at once.
  void start_command(weighing::CommandBit c);
  void finish_command(std::uint8_t error);
  void run_pending();
  bool require_cal_mode();
  [[nodiscard]] double digits_per_kg() const { return digits_per_kg_; }

  Pr5510Config cfg_;
  FillingProcess process_;
  double digits_per_kg_ = 100.0;
  // FSD and the overload margin in digits (lround of the kg values; the
  // config and the digit size are fixed), not rounded every device cycle.
  DINT fsd_digits_ = 0, overload_digits_ = 0;
  std::array<std::uint8_t, weighing::kWindowSize> rd_{};
  std::array<std::uint8_t, 256> reg_valid_{};
  std::array<std::int32_t, 256> reg_{};
  std::array<std::int32_t, 3> limit_{};
  std::array<bool, 3> limit_set_{};

  TIME since_cycle_{};
  TIME since_ms_{};
  std::uint64_t cycles_ = 0;

  // weighing state
  double filtered_kg_ = 0.0;
  double filter_alpha_ = 1.0;  // the filter's share of a new 1 ms sample (from filter_time)
  double zero_offset_kg_ = 0.0;
  double span_gain_ = 1.0;  // from a span calibration
  bool calibrating_ = false;
  DINT gross_ = 0;
  std::int64_t gross100_ = 0;
  DINT tare_ = 0;
  DINT still_ref_ = 0;
  TIME still_for_{};
  bool adu_error_ = false;
  bool master_lost_ = false;  // io_connection_lost() until the next I/O message
  std::array<bool, 3> inputs_{};
  weighing::StatusBits st_{};
  std::uint8_t last_error_ = 0;

  // window state
  std::uint8_t prev_w5_ = 0;
  std::uint8_t prev_w7_ = 0;
  std::uint8_t outputs_ = 0;
  bool write_in_progress_ = false;  // a write-code command waits (tare/zero)
  Pending pending_ = Pending::None;
  TIME pending_for_{};
  std::uint64_t commands_accepted_ = 0;
};

}  // namespace plc::sim

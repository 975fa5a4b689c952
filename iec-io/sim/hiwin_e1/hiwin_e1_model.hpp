// Simulated HIWIN E1 servo drive on PROFINET/PROFIdrive (device model
// "hiwin_e1"), after shared/specs/hiwin-e1-profinet.md. One class, no
// transport: it takes the PLC's telegram bytes and a time step and gives the
// drive's telegram bytes, and serves the parameter channel (spec §6.4) as
// record write/read on index 47 (also 0xB02E/0xB02F).
//
// What it models (spec section in brackets):
// * telegram 3, 9 or 111 (§3), picked by the `telegram` parameter; PNU 922
//   and 930 report it (§6.1, §10.1);
// * the PROFIdrive state machine S1..S5 and fault (§5) with control by PLC
//   (STW1.10: with 0 the last valid control word is kept), OFF1 (ramp Pt537),
//   OFF2 (pulses off, dynamic brake or coast after Pt001 digit 0), OFF3
//   (Pt538 in position mode, Pt30A in speed mode; 0 ms = stop at once);
// * alarms from Table 5.1.1 (§8): FAULT_CODE (tgm 111), PNU 944/945/947/
//   950/952 fault buffer, acknowledge on the rising edge of STW1.7 once the
//   cause is gone; following-error overflow trips AL.d00;
// * sign-of-life (§4.3, §4.6, §10.1): ZSW2 counts 1..15, STW2 is watched
//   once non-zero; more consecutive failures than PNU 925 trips AL.FB1;
// * MDI (§7.6): relative/absolute tasks on the rising edge of STW1.6 with a
//   trapezoidal profile (velocity MDI_VELOCITY x OVERRIDE, acceleration and
//   deceleration MDI_ACC/MDI_DEC of Pt534/Pt537), intermediate stop (STW1.5),
//   reject task (STW1.4, Pt538), a new task replacing a running one, target
//   window and following-error window (ZSW1.10, ZSW1.8);
// * jog (§7.9, Pt533, Pt534/Pt537, Pt53A reversal), homing to a home switch
//   and set reference point (§7.8), overtravel limits (POS_ZSW1.8/9);
// * speed mode (§7.1, telegram 3): NSOLL_B of Pt317, clamp Pt316, ramp
//   generator Pt534/Pt537, NIST_B, G1_XIST1, G1_STW parking/error ack;
// * the PNU dictionary (§6.1-§6.3) with every error number of §6.5;
//   3200h multi-turn clear (refused 16 while enabled, 2 for a while, then 4,
//   or 32), 3215h reset (stops answering for `reset_time`, then restarts in
//   S1), 3216h save to flash; "after power cycle" parameters (Pt001, Pt316,
//   Pt385) take effect at the next restart;
// * an absolute encoder whose multi-turn count survives power_cycle() until
//   cleared through 3200h.
//
// Readings chosen where the manual is silent (each [INF] in the spec):
// * ZSW1.12 mirrors STW1.6 once a task is accepted: it rises in the cycle
//   that accepts the task (with ZSW1.10 already 0) and falls when the PLC
//   drops STW1.6 (the "rising edge active" reading of §10.1, not a toggle).
//   A task that is not accepted is never acknowledged.
// * Ramp times (Pt534, Pt537, Pt538, Pt30A) are from 0 to the reference
//   speed Pt317 (§10.3.6). MDI_ACC/MDI_DEC below 1 count as 1, above 16384
//   as 16384; a task with MDI_VELOCITY <= 0 is not accepted.
// * Telegram 9/111 has no setup submode (§7.6); the blocks run "velocity"
//   as a relative task to the far end of the 32-bit range.
// * ZSW1.8/ZSW1.10 are set only while the pulses are enabled (as the §5
//   example values for telegram 3 show); ZSW1.13 whenever the motor stands.
// * A relative task is relative to the current position setpoint.
// * Homing: move at `homing_speed_rpm` towards the home switch at encoder
//   position `home_switch`; at the switch the position becomes
//   `home_position`; the axis then stops (Pt537) and ZSW1.11 rises. Set
//   reference point (POS_STW2.1 rising) sets the current position to
//   `home_position`.
// * Overtravel: motion into an active limit stops (3062h = 0: Pt538,
//   1: Pt537), the task is dropped, and warning AL.9A0 (WARN_CODE 0x09A0,
//   Yaskawa-style numbering; the manual has no warning table) is shown.
// * 3215h reset is a warm restart: parameter RAM is kept (so "after power
//   cycle" values written before it become active); power_cycle() reloads
//   parameters from flash (3216h = 1 saves them).
// * Torque limits are stored but there is no load model: MELDW.1 stays 1.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <vector>

#include "plc/fb/drive/parameter_channel.hpp"
#include "plc/fb/drive/sign_of_life.hpp"
#include "plc/fb/drive/telegrams.hpp"
#include "plc/io/device_model.hpp"
#include "plc/io/model_params.hpp"

namespace plc::sim {

// Table 5.1.1: fault number (PNU 947) for a fault code (PNU 945/FAULT_CODE);
// 0 if the code is not in the table.
std::uint16_t e1_fault_number(std::uint16_t fault_code);
const char* e1_alarm_name(std::uint16_t fault_code);

struct HiwinE1Config {
  drive::TelegramType telegram = drive::TelegramType::Hiwin111;
  double cu_per_rev = 10000;     // control units per motor revolution
  bool absolute_encoder = true;  // battery-backed multi-turn
  bool sign_of_life_monitoring = true;
  double kv = 400;                        // position loop gain, 1/s
  double standstill_rpm = 10;             // ZSW1.13 motor stopped below this speed
  double speed_tau_ms = 2;                // speed loop lag (speed mode)
  double following_window = 5000;         // CU, ZSW1.8
  double following_error_limit = 200000;  // CU, AL.d00 above it
  double target_window = 10;              // CU, ZSW1.10
  double speed_window_rpm = 30;           // ZSW1.8/10 in speed mode
  double homing_speed_rpm = 60;
  double home_switch = 0;    // encoder CU where the home switch is
  double home_position = 0;  // position value at the reference point
  double neg_limit = -1e18;  // encoder CU of the hardware limits
  double pos_limit = 1e18;
  double initial_position = 0;  // encoder CU at the very first power-up
  double db_time_ms = 50;       // dynamic brake: ref speed -> 0
  double coast_time_ms = 2000;  // free run: ref speed -> 0
  std::int64_t multiturn_clear_ms = 500;
  std::int64_t reset_ms = 100;
};

class HiwinE1Model : public io::DeviceModel {
 public:
  enum class State : std::uint8_t { S1, S2, S3, S4, S5Off1, S5Off3, Fault };

  explicit HiwinE1Model(const io::ModelParams& p);
  explicit HiwinE1Model(const HiwinE1Config& c);

  [[nodiscard]] std::size_t input_size() const override;
  [[nodiscard]] std::size_t output_size() const override;
  void step(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
            std::span<std::uint8_t> to_plc) override;
  io::RecordError read_record(std::uint16_t index, std::span<std::uint8_t> out,
                              std::size_t& length) override;
  io::RecordError write_record(std::uint16_t index, std::span<const std::uint8_t> data) override;
  void power_cycle() override;

  // ---- fault injection (tests) ----
  // Trip an alarm of Table 5.1.1; with `cause_persists` it cannot be
  // acknowledged until clear_alarm_cause(). Returns false for unknown codes.
  bool trip_alarm(std::uint16_t fault_code, bool cause_persists = false);
  void clear_alarm_cause() {
    cause_persists_ = false;
    rest_repeat_ = false;
  }
  void freeze_sign_of_life(bool frozen) { sol_frozen_ = frozen; }
  void set_answering(bool on) {
    answering_ = on;
    refresh_answering();
  }
  void fail_next_multiturn_clear() { fail_next_clear_ = true; }
  // The next 3200h = 1 is refused with 16 as if the motor were enabled (e.g.
  // servo-on from the Thunder tool, which the PLC cannot see).
  void refuse_next_multiturn_clear() { refuse_next_clear_ = true; }
  void set_warning(std::uint16_t warn_code) {
    injected_warning_ = warn_code;
    rest_repeat_ = false;
  }
  // Off: the drive's telegram is encoded from the state every step, and a
  // drive at rest takes the full motion update, as without the shortcuts
  // (tests compare the two).
  void set_shortcuts(bool on) {
    shortcuts_ = on;
    rest_repeat_ = false;
  }

  // ---- inspection (tests, benchmarks) ----
  [[nodiscard]] State state() const { return state_; }
  // The next step may skip to the telegram copy (rest_repeat_; tests).
  [[nodiscard]] bool rest_repeating() const { return rest_repeat_; }
  [[nodiscard]] double encoder_position() const { return enc_; }  // CU incl. multi-turn
  [[nodiscard]] std::int64_t multi_turn() const;
  [[nodiscard]] double position() const { return enc_ + offset_; }
  [[nodiscard]] double velocity() const { return v_act_; }  // CU/s
  [[nodiscard]] std::uint16_t fault_code() const { return fault_code_; }
  [[nodiscard]] bool homed() const { return homed_; }
  [[nodiscard]] bool pulses_enabled() const {
    return state_ == State::S4 || state_ == State::S5Off1 || state_ == State::S5Off3;
  }
  [[nodiscard]] std::int32_t abs_init_value() const { return abs_init_; }
  [[nodiscard]] const HiwinE1Config& config() const { return cfg_; }
  // Parameter value (active one for "after power cycle" parameters); NaN if
  // the PNU does not exist. Sets through the same checks as the channel.
  [[nodiscard]] double parameter(std::uint16_t pnu, std::uint16_t sub = 0) const;
  std::uint16_t set_parameter(std::uint16_t pnu, double value, std::uint16_t sub = 0);

 private:
  struct Param {
    std::uint8_t format = 0x06;
    bool writable = false;
    bool power_cycle = false;  // takes effect after a restart
    bool setup = false;        // only while pulses are off (attribute "Setup")
    double min = 0, max = 65535;
    std::vector<double> value;   // RAM value (one element for a simple parameter)
    std::vector<double> active;  // value in effect (power-cycle parameters)
    std::vector<double> flash;   // saved copy (3216h)
  };
  void build_dictionary();
  void add(std::uint16_t pnu, std::uint8_t fmt, bool rw, double min, double max, double def,
           std::size_t count = 1, bool power_cycle = false);
  double p(std::uint16_t pnu) const;  // active value, element 0
  std::uint16_t read_element(std::uint16_t pnu, std::uint16_t sub, double& v) const;
  std::uint16_t write_element(std::uint16_t pnu, std::uint16_t sub, double v);
  void serve_parameter_request(std::span<const std::uint8_t> req);
  void restart(bool reload_flash);

  // step() but the rest repeat (rest_repeat_), out of line: the repeat
  // saves no registers for it.
  [[gnu::noinline]] void step_full(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
                                   std::span<std::uint8_t> to_plc);
  // step_full()'s parts, each called from it alone, every step: inline, so
  // they cost no call and save no registers.
  [[gnu::always_inline]] inline void update_state_machine(bool rise_ack);
  // Returns true when it took the rest shortcut and that changed nothing
  // (see rest_repeat_).
  [[gnu::always_inline]] inline bool update_position_mode(double dt, bool rise_task,
                                                          bool rise_homing, bool rise_setref);
  void update_speed_mode(double dt);
  void coast(double dt);
  void follow(double dt);
  void enter_fault(std::uint16_t code);
  [[gnu::always_inline]] inline void write_inputs(std::span<std::uint8_t> to_plc);
  [[gnu::always_inline]] inline void put_inputs(std::span<std::uint8_t> to_plc);
  void encode_inputs(std::span<std::uint8_t> to_plc) const;
  bool move_to(double target, double vmax, double a, double d, double dt);
  void ramp_velocity(double vt, double a, double d, double dt);
  double ref_speed() const;             // CU/s at 100 % (Pt317)
  double accel_of_ms(double ms) const;  // CU/s^2 for a ramp time (0 = infinite)

  HiwinE1Config cfg_;
  std::map<std::uint16_t, Param> dict_;
  // Active values the cycle uses, copied from the dictionary after every
  // write and restart (keeps map look-ups out of step()).
  struct Active {
    double pt001 = 0, pt30a = 0, pt316 = 0, pt317 = 0, pt533 = 0, pt534 = 0, pt537 = 0, pt538 = 0,
           pt53a = 0, ot_mode = 0, sol_tolerance = 5;
    // accel_of_ms() of the ramp times, which depend on Pt317 too.
    double acc534 = 0, acc537 = 0, acc538 = 0, acc30a = 0, acc_coast = 0, acc_db = 0;
    // The sign-of-life monitor's tolerance as it takes it (PNU 925).
    std::uint16_t sol_tol = 5;
  } act_;
  const double stop_thr_;  // CU/s: below this |speed| the motor stands (ZSW1.13)
  // follow(): the lag's factor for the last step length (one exp() per change).
  double follow_dt_ = -1, follow_alpha_ = 0;
  void refresh_active();

  // control word as last accepted (control by PLC), and its previous value
  std::uint16_t stw1_ = 0, prev_stw1_ = 0, pos_stw2_prev_ = 0;
  drive::Telegram111Out cmd_;  // setpoints (tgm 9 mapped onto the 111 fields)
  // The last telegram 111 decoded, and its bytes (decode_111).
  // `same`: the bytes but STW2 are those of the last telegram decoded.
  [[gnu::always_inline]] inline const drive::Telegram111Out& decode_111(
      std::span<const std::uint8_t> b, bool& same);
  drive::Telegram111Out decoded_;
  std::array<std::uint8_t, drive::Telegram111Out::kBytes> decoded_bytes_{};
  bool decoded_valid_ = false;
  bool mdi_selected_ = false;
  std::int32_t nsoll_b_ = 0;
  std::uint16_t g1_stw_ = 0;

  State state_ = State::S1;
  bool answering_ = true;
  double reboot_left_ms_ = 0;
  // answering() (DeviceModel's kept flag): answering_ and no reboot
  // running, refreshed at each change of either.
  void refresh_answering() { set_answering_now(answering_ && reboot_left_ms_ <= 0); }

  // motion, all in encoder CU
  double enc_ = 0, offset_ = 0;
  double p_set_ = 0, v_set_ = 0, v_act_ = 0;
  bool homed_ = false;
  bool task_active_ = false, task_ack_ = false, task_done_ = true, task_rejecting_ = false;
  double task_target_ = 0, task_v_ = 0, task_a_ = 0, task_d_ = 0;
  bool jog_active_ = false, homing_ = false, homing_found_ = false, homing_settle_ = false;
  double homing_dir_ = 1;
  bool overtravel_neg_ = false, overtravel_pos_ = false;
  bool g1_ack_in_progress_ = false;
  std::uint16_t g1_prev_ = 0;
  double speed_target_ = 0;  // speed mode: setpoint after the clamp, CU/s

  // faults and warnings
  std::uint16_t fault_code_ = 0;
  bool cause_persists_ = false;
  std::uint16_t injected_warning_ = 0;
  std::array<std::uint16_t, 64> fault_codes_{}, fault_numbers_{};
  std::uint16_t fault_msg_counter_ = 0, fault_situations_ = 0;

  // sign-of-life
  std::uint8_t sol_ = 0;
  bool sol_frozen_ = false;
  drive::SignOfLifeMonitor sol_monitor_;

  // 3200h multi-turn clear
  std::int32_t abs_init_ = 0;
  double abs_init_left_ms_ = 0;
  bool fail_next_clear_ = false;
  bool refuse_next_clear_ = false;
  bool clear_will_fail_ = false;

  // The drive's telegram as last encoded (encode_inputs), and everything it
  // was encoded from but the sign-of-life (doubles as their bits): the
  // conveyor stands still most of the time, so most steps only copy it and
  // put the new ZSW2 in.
  using InputsKey = std::array<std::uint64_t, 9>;
  [[nodiscard]] InputsKey inputs_key() const;
  InputsKey encoded_key_{};
  bool encoded_valid_ = false;
  bool shortcuts_ = true;  // set_shortcuts()
  // The last step() was a full one (telegram 111) that found the drive at
  // rest in S4 with nothing to start (the rest shortcut) and changed
  // nothing that a step reads but the sign-of-life: its control words were
  // those of the step before, the state machine stayed in S4, the rest
  // shortcut's writes left every bit as it was and the telegram stayed
  // encoded. Cleared by everything else that changes the model (the public
  // calls, restart(), enter_fault()). While it holds, a step with the same
  // PLC bytes but STW2 computes that same nothing again, and step() does
  // only the sign-of-life and the telegram copy (the conveyor stands most
  // of the time).
  bool rest_repeat_ = false;
  std::array<std::uint8_t, drive::Telegram111In::kBytes> encoded_{};

  // parameter channel: the pending response
  std::array<std::uint8_t, io::kRecordMaxBytes> response_{};
  std::size_t response_len_ = 0;
};

}  // namespace plc::sim

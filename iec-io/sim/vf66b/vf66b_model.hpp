// Simulated Toyo VF66B inverter with the DNET66-Z DeviceNet option (device
// model "vf66b"), after shared/specs/toyo-vf66-devicenet.md. One class, no
// transport: it consumes the output assembly the master sends, steps the
// drive, and produces the input assembly; it answers explicit services on
// the Parameter (0x0F), Motor Data (0x28), Control Supervisor (0x29) and
// AC/DC Drive (0x2A) objects through query_record (explicit_message.hpp).
// The DeviceNet objects 0x01/0x03/0x04/0x05 belong to the slave that hosts
// the model (dnslave), not to this class.
//
// What it models (spec section in brackets):
// * J-09/J-10 select the output/input assembly, J-11 the SpeedScale, J-12
//   the monitors of instance 140, b-10/b-11 the reference and run command
//   source, read at power-up only; power_cycle() re-reads them from
//   settings() (§7.2, §9, §13.1.1);
// * the Control Supervisor state machine (§5.2: Startup for startup_time,
//   Not_Ready, Ready, Enabled, Stopping, Fault_Stop, Faulted) and the
//   Run1/Run2 event matrix (§5.1, Table 3.4.3);
// * a linear speed ramp (accel_time/decel_time from 0 to top speed), coast
//   after a trip (coast_time from top speed), an ideal motor (actual speed =
//   ramp output); AtReference when the ramp has reached the reference;
// * terminal ST-F (§9.2): off, the run bits have no effect and a running
//   drive stops;
// * faults 1..32 (§7.8) latched until a Fault Reset 0->1 edge with the cause
//   gone; fault 18 on io_connection_lost() under network control (§12);
//   external faults 1-4 from the extended output bits Ex-Fail.1..4;
// * the extended assemblies' status bits, fault field, monitors (§7.6) and
//   ProtectErrorCode/monitor triple (§7.7);
// * the restart-after-reset behaviour of §9.2/§13.4 item 21 as an option
//   (restart_after_reset), strict ODVA edges by default;
// * NetRef (0x2A attr 4) at power-up: network iff b-10 = 3, else local
//   (manual §4.1, spec §9.2); NetCtrl (0x29 attr 5) likewise from b-11.
//
// Explicit Set and I/O, which wins [reading]. Every Set/Get attribute the
// tables mark supported takes Set_Attribute_Single (Tables 3.3.2, 3.4.2,
// 3.5.2), also those the active output assembly carries: Run1, Run2,
// FaultRst, NetCtrl, NetRef and SpeedRef (Table 3.7.1; Start/Rev, Fault
// Reset2 and Speed Reference2 of 100..108, §7.5). The manual makes no
// exception and says nothing about precedence, so each such datum holds the
// last value written, by an explicit Set or by a consumed output message:
// * while the I/O connection is established and polled, every poll command
//   overwrites it; an explicit Set stands until the next poll (a FaultRst
//   0->1 edge is taken when it is written, so an explicit fault reset works
//   whatever the next poll carries; a Run1 0->1 written between two polls
//   is a Run event of Table 3.4.3, the poll after it a Stop if it carries
//   Run1 = Run2 = 0);
// * without an I/O connection (not allocated, Configuring, Timed Out,
//   released) nothing overwrites it: an explicit Set stands; the values of
//   the last poll stand likewise until written again (a timeout under
//   network control trips fault 18, §12);
// * the in-process sim plugin delivers the outputs every cycle (step()):
//   each step is a new output message, served after that cycle's explicit
//   requests, so there the outputs always win.
// Hosts tell the model which steps carry a new message through step_io()
// (the DeviceNet slave: a poll command or a Set of the output assembly's
// data, in arrival order with the explicit requests). NetCtrl/NetRef and
// b-11/b-10 decide whether the network run command and reference are used
// at all (CtrlFromNet/RefFromNet), whichever path wrote them. In 100..108
// Start with Rev off is Run1, with Rev on Run2, and SpeedRef reads and
// writes Speed Reference2 in r/min x 2^SpeedScale.
//
// Readings chosen where the manual is silent: see fblocks/acdrive/README.md
// ("Readings of §13.4"); each is also marked [reading] where the code acts
// on it.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "plc/fb/acdrive/assemblies.hpp"
#include "plc/io/device_model.hpp"
#include "plc/io/model_params.hpp"

namespace plc::sim {

// Inverter control mode (§6.2): V/f, induction-motor vector, ED-motor vector.
enum class Vf66bMode : std::uint8_t { Vf, ImVector, EdVector };

// Keypad settings and simulation parameters. The J-/b- settings act only at
// power-up (construction and power_cycle()).
struct Vf66bConfig {
  // DeviceNet settings, Table 4.1 (§9.1)
  unsigned j09 = 0;  // output instance 20, 21, 100..108
  unsigned j10 = 0;  // input instance 70, 71, 120..132, 140
  int j11 = 3;       // SpeedScale, -126..127
  unsigned j12 = 3;  // MonitorDataNo. 0..119
  unsigned j14 = 0;  // date/time from communication
  // command sources, Table 4.3 (§9.2)
  unsigned b09 = 1;  // source when "interlocked" (2 = comm option)
  unsigned b10 = 0;  // speed reference source (3 = comm option)
  unsigned b11 = 0;  // run command source (3 = comm option)
  bool i00 = false;  // PLC-L on: words 1-2 of 100..108 are only PLC relays
  Vf66bMode mode = Vf66bMode::ImVector;
  unsigned poles = 4;
  // motor data (0x28 attrs 3/6/7)
  std::uint8_t motor_type = 7;        // squirrel-cage induction
  std::uint16_t rated_current = 100;  // 100 mA units
  std::uint16_t rated_voltage = 200;  // V
  unsigned voltage_class = 200;       // 200 or 400 (monitor scaling, §7.6)
  // drive behaviour
  double top_speed_rpm = 1800;                  // "top" (maximum speed): 20000 counts
  double accel_time_s = 5;                      // 0 -> top speed
  double decel_time_s = 5;                      // top speed -> 0
  double coast_time_s = 2;                      // free run after a trip, top speed -> 0
  double local_speed_rpm = 0;                   // reference when RefFromNet = 0
  TIME startup_time = std::chrono::seconds(1);  // power-up LED test (§8)
  bool st_f = true;                             // ST-F terminal at power-up
  bool main_power = true;
  bool comm_loss_trip = true;        // fault 18 on I/O connection loss (§12)
  bool restart_after_reset = false;  // §13.4 item 21
  acdrive::MonitorByteOrder monitor_order = acdrive::MonitorByteOrder::LittleEndian;
  // fault switch: trip fault_code (1..32) at virtual time fault_at
  std::uint8_t fault_code = 0;
  TIME fault_at{};
  bool fault_persists = false;  // the cause stays until clear_fault_cause()
};

// Parses `params:` strictly (unknown keys are errors). Keys: j09, j10, j11,
// j12, j14, b09, b10, b11, i00, mode (vf|im_vector|ed_vector), poles,
// motor_type, rated_current, rated_voltage, voltage_class, top_speed_rpm,
// accel_time, decel_time, coast_time (durations), local_speed_rpm,
// startup_time, st_f, main_power, comm_loss (trip|ignore),
// restart_after_reset, monitor_order (little_endian|manual_literal),
// fault_code, fault_at, fault_persists.
Vf66bConfig vf66b_config_from(const io::ModelParams& p);

// The Run/Stop event of Table 3.4.3 (§5.1) from the previous and present
// levels of Run1/Run2.
enum class RunEvent : std::uint8_t { None, Stop, Run1, Run2 };
RunEvent run_event(bool prev_run1, bool prev_run2, bool run1, bool run2);

class Vf66bModel : public io::DeviceModel {
 public:
  explicit Vf66bModel(const io::ModelParams& p);
  explicit Vf66bModel(const Vf66bConfig& c);

  [[nodiscard]] std::size_t input_size() const override;
  [[nodiscard]] std::size_t output_size() const override;
  void step(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
            std::span<std::uint8_t> to_plc) override;
  void step_io(TIME now, TIME dt, std::span<const std::uint8_t> from_plc, bool new_message,
               std::span<std::uint8_t> to_plc) override;
  io::RecordError query_record(std::uint16_t index, std::span<const std::uint8_t> request,
                               std::span<std::uint8_t> out, std::size_t& length) override;
  void power_cycle() override;
  void io_connection_lost() override;

  // ---- keypad (takes effect at the next power_cycle()) ----
  Vf66bConfig& settings() { return settings_; }

  // ---- fault switches and terminals (tests, dnslave) ----
  // Trip protection `code` (1..32, not 3/4); with `cause_persists` a reset
  // does not clear it until clear_fault_cause(). false for other codes.
  bool trip(std::uint8_t code, bool cause_persists = false);
  void clear_fault_cause() { persistent_ = 0; }
  void set_st_f(bool on) { st_f_ = on; }
  void set_main_power(bool on) { main_power_ = on; }
  void set_answering(bool on) { set_answering_now(on); }

  // ---- inspection ----
  [[nodiscard]] acdrive::DriveState state() const { return state_; }
  [[nodiscard]] double speed_rpm() const { return speed_; }  // signed, + = forward
  [[nodiscard]] double reference_rpm() const;                // signed target of the ramp
  [[nodiscard]] std::uint32_t faults() const { return faults_; }
  [[nodiscard]] bool faulted() const { return faulted_; }
  [[nodiscard]] bool running1() const { return running1_; }
  [[nodiscard]] bool running2() const { return running2_; }
  [[nodiscard]] bool ctrl_from_net() const;
  [[nodiscard]] bool ref_from_net() const;
  [[nodiscard]] bool at_reference() const;
  [[nodiscard]] int speed_scale() const { return speed_scale_; }
  [[nodiscard]] std::uint8_t output_instance() const { return out_inst_; }
  [[nodiscard]] std::uint8_t input_instance() const { return in_inst_; }
  [[nodiscard]] const Vf66bConfig& active() const { return act_; }  // settings read at power-up
  [[nodiscard]] std::uint32_t bad_frames() const { return bad_frames_; }

 private:
  void power_up();
  void consume(std::span<const std::uint8_t> from_plc);
  void update_state(double dt_s);
  void update_ramp(double dt_s);
  void produce(std::span<std::uint8_t> to_plc) const;
  void fault_reset_edge();
  [[nodiscard]] bool ready_attr() const;
  [[nodiscard]] std::int16_t bus_of(double rpm) const;  // r/min x 2^SpeedScale, saturated
  [[nodiscard]] std::int16_t speed_actual_bus() const;
  [[nodiscard]] std::uint16_t monitor_value(unsigned number) const;
  [[nodiscard]] acdrive::ExtStatusBits status_bits() const;
  // explicit services
  io::RecordError get_attribute(std::uint8_t cls, std::uint8_t attr, std::span<std::uint8_t> out,
                                std::size_t& length) const;
  io::RecordError set_attribute(std::uint8_t cls, std::uint8_t attr,
                                std::span<const std::uint8_t> data);

  Vf66bConfig settings_;  // keypad (edited any time)
  Vf66bConfig act_;       // read at power-up
  std::uint8_t out_inst_ = 20, in_inst_ = 70;
  int speed_scale_ = 3;
  std::array<std::uint8_t, 3> monitors_{};
  bool ctrl_permitted_ = false, ref_permitted_ = false;

  acdrive::DriveState state_ = acdrive::DriveState::Startup;
  double startup_left_s_ = 0;
  bool st_f_ = true, main_power_ = true;

  // Control Supervisor / AC/DC Drive attributes, written by explicit Sets
  // and by output messages (the last write holds, see above)
  bool run1_ = false, run2_ = false, fault_rst_ = false;  // 100..108: Start/Rev, Fault Reset2
  bool net_ctrl_ = false, net_ref_ = false;
  std::int16_t speed_ref_ = 0;  // bus units (attr 8)
  double ext_ref_rpm_ = 0;      // 100..108: Speed Reference2 (and attr 8) in r/min
  std::uint8_t motor_type_ = 7;
  std::uint16_t rated_current_ = 100, rated_voltage_ = 200;
  bool running1_ = false, running2_ = false;
  bool faulted_ = false;
  bool reset_pending_ = false;                  // a reset edge was seen this step
  bool just_reset_ = false;                     // a reset cleared the faults in this step
  bool prev_run1_ = false, prev_run2_ = false;  // levels at the previous step

  // faults
  std::uint32_t faults_ = 0;      // latched fault field (bit n-1 = code n)
  std::uint32_t persistent_ = 0;  // causes still present
  std::uint32_t pending_ = 0;     // detected, not yet acted on by the state machine
  bool injected_ = false;         // the fault switch fired (once per model, not per power-up)

  // motor
  double speed_ = 0;  // r/min, signed
  double torque_pct_ = 0;
  TIME now_{};
  std::uint32_t bad_frames_ = 0;
};

}  // namespace plc::sim

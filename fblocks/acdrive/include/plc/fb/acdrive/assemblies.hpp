// The I/O assemblies of the Toyo VF66B with DNET66-Z (toyo-vf66-devicenet.md
// §7): the ODVA AC Drive profile instances 20/21 (output) and 70/71 (input)
// and the VF66B extended instances 100-108 (output), 120-132 and 140
// (input), selected at power-up by J-09 (output) and J-10 (input), §7.2.
//
// "Output" is master -> drive, "input" drive -> master (§0). DeviceNet data
// are little-endian (§0). The reserved-bit rule of §2: a receiver ignores
// reserved bits of an output assembly (decode_* drop them), a sender sets
// reserved bits of an input assembly to 0 (encode_* write every byte, and
// reserved bits and the "not specified" words are 0 unless a field for
// them is set).
//
// Both the drive blocks and the simulated VF66B use these codecs; the tests
// check them against the byte layouts of the spec tables, not against each
// other.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace plc::acdrive {

// ---------------------------------------------------------------- §7.2
inline constexpr std::uint8_t kMaxJ09 = 10;
inline constexpr std::uint8_t kMaxJ10 = 15;

// Output (consumed) instance for J-09 = 0..10; 0 for an invalid value.
constexpr std::uint8_t output_instance(unsigned j09) {
  if (j09 == 0) return 20;
  if (j09 == 1) return 21;
  if (j09 <= kMaxJ09) return static_cast<std::uint8_t>(98 + j09);
  return 0;
}
// Input (produced) instance for J-10 = 0..15; 0 for an invalid value.
constexpr std::uint8_t input_instance(unsigned j10) {
  if (j10 == 0) return 70;
  if (j10 == 1) return 71;
  if (j10 <= 14) return static_cast<std::uint8_t>(118 + j10);
  if (j10 == 15) return 140;
  return 0;
}
// Length in bytes of an output instance (20, 21, 100..108); 0 if unknown.
constexpr std::size_t output_size(unsigned instance) {
  if (instance == 20 || instance == 21) return 4;
  if (instance >= 100 && instance <= 108) return 2 * (instance - 100 + 4);
  return 0;
}
// Length in bytes of an input instance (70, 71, 120..132, 140); 0 if unknown.
constexpr std::size_t input_size(unsigned instance) {
  if (instance == 70 || instance == 71) return 4;
  if (instance >= 120 && instance <= 132) return 2 * (instance - 120 + 6);
  if (instance == 140) return 8;
  return 0;
}
constexpr bool is_extended_output(unsigned instance) { return instance >= 100 && instance <= 108; }

// Drive State of the Control Supervisor (0x29 attr 6; assembly 71 byte 1),
// §5 and Table 6.3.
enum class DriveState : std::uint8_t {
  VendorSpecific = 0,
  Startup = 1,
  NotReady = 2,
  Ready = 3,
  Enabled = 4,
  Stopping = 5,
  FaultStop = 6,
  Faulted = 7,
};
const char* to_string(DriveState s);

// ---------------------------------------------------------------- §7.3
// Output assembly 20, Basic Speed Control Output (Table 3.7.1).
struct Output20 {
  static constexpr std::size_t kSize = 4;
  static constexpr std::uint8_t kRunFwd = 0x01;      // byte 0 bit 0 (Run1)
  static constexpr std::uint8_t kFaultReset = 0x04;  // byte 0 bit 2 (0->1)
  bool run_fwd = false;
  bool fault_reset = false;
  std::int16_t speed_ref = 0;  // r/min x 2^SpeedScale (0x2A attr 8)
  bool operator==(const Output20&) const = default;
};
// Output assembly 21, Extended Speed Control Output (Table 3.7.1).
struct Output21 {
  static constexpr std::size_t kSize = 4;
  static constexpr std::uint8_t kRunFwd = 0x01;      // bit 0, Run1
  static constexpr std::uint8_t kRunRev = 0x02;      // bit 1, Run2
  static constexpr std::uint8_t kFaultReset = 0x04;  // bit 2
  static constexpr std::uint8_t kNetCtrl = 0x20;     // bit 5, 0x29 attr 5
  static constexpr std::uint8_t kNetRef = 0x40;      // bit 6, 0x2A attr 4
  bool run_fwd = false;
  bool run_rev = false;
  bool fault_reset = false;
  bool net_ctrl = false;
  bool net_ref = false;
  std::int16_t speed_ref = 0;
  bool operator==(const Output21&) const = default;
};

// ---------------------------------------------------------------- §7.4
// Input assembly 70, Basic Speed Control Input (Table 3.7.2).
struct Input70 {
  static constexpr std::size_t kSize = 4;
  static constexpr std::uint8_t kFaulted = 0x01;   // bit 0
  static constexpr std::uint8_t kRunning1 = 0x04;  // bit 2
  bool faulted = false;
  bool running1 = false;
  std::int16_t speed_actual = 0;  // r/min x 2^SpeedScale (0x2A attr 7)
  bool operator==(const Input70&) const = default;
};
// Input assembly 71, Extended Speed Control Input (Table 3.7.2).
struct Input71 {
  static constexpr std::size_t kSize = 4;
  static constexpr std::uint8_t kFaulted = 0x01;
  static constexpr std::uint8_t kWarning = 0x02;
  static constexpr std::uint8_t kRunning1 = 0x04;
  static constexpr std::uint8_t kRunning2 = 0x08;
  static constexpr std::uint8_t kReady = 0x10;
  static constexpr std::uint8_t kCtrlFromNet = 0x20;
  static constexpr std::uint8_t kRefFromNet = 0x40;
  static constexpr std::uint8_t kAtReference = 0x80;
  bool faulted = false;
  bool warning = false;
  bool running1 = false;
  bool running2 = false;
  bool ready = false;
  bool ctrl_from_net = false;
  bool ref_from_net = false;
  bool at_reference = false;
  DriveState state = DriveState::VendorSpecific;  // byte 1
  std::int16_t speed_actual = 0;
  bool operator==(const Input71&) const = default;
};

// ---------------------------------------------------------------- §7.5
// Output assemblies 100-108 (Table 6.2). Bytes 0-3: bit signals, named as in
// the manual (its built-in-PLC relay I00020 + 8*byte + bit in brackets).
struct ExtOutputBits {
  // byte 0
  bool start = false;         // I00020 run command
  bool jog = false;           // I00021
  bool rev = false;           // I00022 reverse command (NOT fault reset as in 20/21)
  bool excitation = false;    // I00023 initial-excitation command
  bool dc_brake = false;      // I00024
  bool fault_reset2 = false;  // I00025 protection-state reset
  bool preset1 = false;       // I00026
  bool preset2 = false;       // I00027
  // byte 1
  bool preset3 = false;         // I00028
  bool acc_dec_sel1 = false;    // I00029
  bool acc_dec_sel2 = false;    // I0002A
  bool mrh_up = false;          // I0002B
  bool mrh_down = false;        // I0002C
  bool spd_hold = false;        // I0002D
  bool s_arc_off = false;       // I0002E
  bool max_spd_reduce = false;  // I0002F
  // byte 2
  bool droop_off = false;       // I00030
  bool atr_mode = false;        // I00031 (printed "ATRMdode")
  bool rev_gnd = false;         // I00032 (meaning unknown)
  bool ex_fail1 = false;        // I00033 external fault 1
  bool ex_fail2 = false;        // I00034
  bool ex_fail3 = false;        // I00035
  bool ex_fail4 = false;        // I00036
  bool ex_fail1_no86a = false;  // I00037 external fault 1, no 86A relay
  // byte 3
  bool ex_fail2_no86a = false;  // I00038
  bool ex_fail3_no86a = false;  // I00039
  bool ex_fail4_no86a = false;  // I0003A
  bool trace_trg = false;       // I0003B
  bool second_motor = false;    // I0003C
  bool emg_stop = false;        // I0003D emergency stop input
  bool pgm_next = false;        // I0003E
  bool spd_ref_term = false;    // I0003F
  bool operator==(const ExtOutputBits&) const = default;
  [[nodiscard]] std::uint32_t pack() const;  // bit n = byte n/8, bit n%8
  static ExtOutputBits unpack(std::uint32_t bits);
};
struct ExtOutput {
  std::uint8_t instance = 100;  // 100..108: its length (§7.2)
  ExtOutputBits bits;
  std::int16_t speed_ref2 = 0;                   // word 3: 20000 = top speed
  std::int16_t torque_ref = 0;                   // word 4: 5000 = 100 %
  std::uint8_t day = 0;                          // word 5 low (instance >= 101; J-14 = 1)
  std::uint8_t month = 0;                        // word 5 high
  std::uint8_t minute = 0;                       // word 6 low (instance >= 102)
  std::uint8_t hour = 0;                         // word 6 high
  std::array<std::uint16_t, 6> plc_registers{};  // words 7-12 (i00014-i00019): built-in PLC only
  bool operator==(const ExtOutput&) const = default;
};

// ---------------------------------------------------------------- §7.6
// Status bytes 0-1 (shared by 120-132 and, bytes 0 and byte 1 bits 0-1, 140).
struct ExtStatusBits {
  // byte 0
  bool run_or_jog_input = false;  // run or jog command being input
  bool inverter_running = false;  // includes decelerating to stop
  bool jog_operation = false;
  bool reverse_command = false;
  bool dc_excitation = false;
  bool power_failure = false;  // power failure in progress
  bool auto_tuning = false;
  bool gate_active = false;  // output switching
  // byte 1
  bool initial_excitation = false;
  bool dc_braking = false;
  bool ext_db_or_comm_error = false;  // bit 2: external DB protection or communication error
  // bit 3 reserved
  bool ext_signal1 = false;  // bits 4..7: external signal inputs 1-4
  bool ext_signal2 = false;
  bool ext_signal3 = false;
  bool ext_signal4 = false;
  bool operator==(const ExtStatusBits&) const = default;
};
// Bytes 6-7 (120-132). Byte 6 is garbled in the manual (§13.4 item 9): the
// comparison of each speed-detect bit is unknown, bit 0 unlabeled (reserved).
struct ExtDetectBits {
  // byte 6
  bool speed_detect1_a = false;  // bit 1
  bool speed_detect1_b = false;  // bit 2
  bool speed_detect1_c = false;  // bit 3
  bool speed_detect2_a = false;  // bit 4
  bool speed_detect2_b = false;  // bit 5
  bool speed_detect2_c = false;  // bit 6
  bool setting_reached = false;  // bit 7
  // byte 7
  bool torque_detect = false;
  bool abs_torque_detect = false;
  bool power_failure_detected = false;
  bool overload_prealarm = false;
  bool fault_retry = false;
  bool reverse_rotation = false;
  bool second_setting_block = false;
  bool cooling_fan_failure = false;
  bool operator==(const ExtDetectBits&) const = default;
};
struct ExtInput {
  std::uint8_t instance = 120;  // 120..132: its length (§7.2)
  ExtStatusBits status;
  std::uint32_t faults = 0;  // bytes 2-5 LE: bit n-1 = fault code n (§7.6, §7.8)
  ExtDetectBits detect;
  // words 5-14, each from the first instance that carries it
  std::int16_t speed_actual2 = 0;                // 20000 = top speed
  std::int16_t arc_out = 0;                      // ramp output, 20000 = top
  std::uint16_t motor_current = 0;               // 10000 = 100 % inverter rated current (>= 121)
  std::int16_t torque_command = 0;               // 5000 = 100 % (>= 122)
  std::uint16_t dc_voltage = 0;                  // 10/V (200 V class), 5/V (400 V) (>= 123)
  std::uint16_t output_voltage = 0;              // 20/V (200 V class), 10/V (400 V) (>= 124)
  std::uint16_t output_frequency = 0;            // 20000 = top (>= 125)
  std::uint16_t ol_precounter = 0;               // 10000 = 100 % (>= 126)
  std::int16_t motor_temperature = 0;            // 10/degC (>= 127)
  std::uint16_t motor_flux = 0;                  // 1024 = 100 % (>= 128)
  std::array<std::uint16_t, 4> plc_registers{};  // words 15-18 (o0001A-o0001D): built-in PLC only
  bool operator==(const ExtInput&) const = default;
};

// ---------------------------------------------------------------- §7.7
// Monitors 2 and 3 of instance 140 are printed high byte first (§13.4 item 6).
enum class MonitorByteOrder : std::uint8_t { LittleEndian, ManualLiteral };
struct Input140 {
  static constexpr std::size_t kSize = 8;
  ExtStatusBits status;                    // byte 0 and byte 1 bits 0-1 only
  std::uint8_t protect_code = 0;           // byte 1 bits 7..2 (bit 2 = LSB), 0..32
  std::array<std::uint16_t, 3> monitor{};  // Monitor Number1..3 data (J-12)
  bool operator==(const Input140&) const = default;
};

// ---------------------------------------------------------------- codecs
// encode_*: write exactly the assembly's bytes into `out` (out.size() must
// be the assembly's size; returns false and writes nothing otherwise).
// decode_*: return false when `in` has the wrong size.
bool encode(const Output20& v, std::span<std::uint8_t> out);
bool encode(const Output21& v, std::span<std::uint8_t> out);
bool encode(const ExtOutput& v, std::span<std::uint8_t> out);
bool encode(const Input70& v, std::span<std::uint8_t> out);
bool encode(const Input71& v, std::span<std::uint8_t> out);
bool encode(const ExtInput& v, std::span<std::uint8_t> out);
bool encode(const Input140& v, std::span<std::uint8_t> out,
            MonitorByteOrder order = MonitorByteOrder::LittleEndian);

bool decode(std::span<const std::uint8_t> in, Output20& v);
bool decode(std::span<const std::uint8_t> in, Output21& v);
// The instance is taken from v.instance (its length must match in.size()).
bool decode(std::span<const std::uint8_t> in, ExtOutput& v);
bool decode(std::span<const std::uint8_t> in, Input70& v);
bool decode(std::span<const std::uint8_t> in, Input71& v);
bool decode(std::span<const std::uint8_t> in, ExtInput& v);
bool decode(std::span<const std::uint8_t> in, Input140& v,
            MonitorByteOrder order = MonitorByteOrder::LittleEndian);

// J-12 MonitorDataNo. 0..119 -> the monitor numbers (1..10) of Monitor 1..3:
// the J-12-th 3-combination of {1..10} in lexicographic order (Table 6.5.1,
// §7.7). {0,0,0} for a value outside 0..119.
std::array<std::uint8_t, 3> monitor_selection(unsigned j12);

}  // namespace plc::acdrive

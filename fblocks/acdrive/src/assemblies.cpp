#include "plc/fb/acdrive/assemblies.hpp"

#include <algorithm>

#include "plc/io/byte_order.hpp"

namespace plc::acdrive {

using io::load_le;
using io::store_le;

const char* to_string(DriveState s) {
  switch (s) {
    case DriveState::VendorSpecific:
      return "Vendor specific";
    case DriveState::Startup:
      return "Startup";
    case DriveState::NotReady:
      return "Not_Ready";
    case DriveState::Ready:
      return "Ready";
    case DriveState::Enabled:
      return "Enabled";
    case DriveState::Stopping:
      return "Stopping";
    case DriveState::FaultStop:
      return "Fault_Stop";
    case DriveState::Faulted:
      return "Faulted";
  }
  return "?";
}

namespace {

std::uint8_t bit(bool b, std::uint8_t mask) { return b ? mask : std::uint8_t{0}; }

// The bits of ExtOutputBits in wire order (bit n = byte n/8, bit n%8).
constexpr std::array<bool ExtOutputBits::*, 32> kExtOutBits = {
    &ExtOutputBits::start,
    &ExtOutputBits::jog,
    &ExtOutputBits::rev,
    &ExtOutputBits::excitation,
    &ExtOutputBits::dc_brake,
    &ExtOutputBits::fault_reset2,
    &ExtOutputBits::preset1,
    &ExtOutputBits::preset2,
    &ExtOutputBits::preset3,
    &ExtOutputBits::acc_dec_sel1,
    &ExtOutputBits::acc_dec_sel2,
    &ExtOutputBits::mrh_up,
    &ExtOutputBits::mrh_down,
    &ExtOutputBits::spd_hold,
    &ExtOutputBits::s_arc_off,
    &ExtOutputBits::max_spd_reduce,
    &ExtOutputBits::droop_off,
    &ExtOutputBits::atr_mode,
    &ExtOutputBits::rev_gnd,
    &ExtOutputBits::ex_fail1,
    &ExtOutputBits::ex_fail2,
    &ExtOutputBits::ex_fail3,
    &ExtOutputBits::ex_fail4,
    &ExtOutputBits::ex_fail1_no86a,
    &ExtOutputBits::ex_fail2_no86a,
    &ExtOutputBits::ex_fail3_no86a,
    &ExtOutputBits::ex_fail4_no86a,
    &ExtOutputBits::trace_trg,
    &ExtOutputBits::second_motor,
    &ExtOutputBits::emg_stop,
    &ExtOutputBits::pgm_next,
    &ExtOutputBits::spd_ref_term,
};

// Status bytes 0-1 in wire order; nullptr = reserved (byte 1 bit 3).
constexpr std::array<bool ExtStatusBits::*, 16> kStatusBits = {
    &ExtStatusBits::run_or_jog_input,     &ExtStatusBits::inverter_running,
    &ExtStatusBits::jog_operation,        &ExtStatusBits::reverse_command,
    &ExtStatusBits::dc_excitation,        &ExtStatusBits::power_failure,
    &ExtStatusBits::auto_tuning,          &ExtStatusBits::gate_active,
    &ExtStatusBits::initial_excitation,   &ExtStatusBits::dc_braking,
    &ExtStatusBits::ext_db_or_comm_error, nullptr,
    &ExtStatusBits::ext_signal1,          &ExtStatusBits::ext_signal2,
    &ExtStatusBits::ext_signal3,          &ExtStatusBits::ext_signal4,
};

// Bytes 6-7 in wire order; nullptr = reserved (byte 6 bit 0, unlabeled).
constexpr std::array<bool ExtDetectBits::*, 16> kDetectBits = {
    nullptr,
    &ExtDetectBits::speed_detect1_a,
    &ExtDetectBits::speed_detect1_b,
    &ExtDetectBits::speed_detect1_c,
    &ExtDetectBits::speed_detect2_a,
    &ExtDetectBits::speed_detect2_b,
    &ExtDetectBits::speed_detect2_c,
    &ExtDetectBits::setting_reached,
    &ExtDetectBits::torque_detect,
    &ExtDetectBits::abs_torque_detect,
    &ExtDetectBits::power_failure_detected,
    &ExtDetectBits::overload_prealarm,
    &ExtDetectBits::fault_retry,
    &ExtDetectBits::reverse_rotation,
    &ExtDetectBits::second_setting_block,
    &ExtDetectBits::cooling_fan_failure,
};

template <class S, std::size_t N>
std::uint32_t pack_bits(const S& s, const std::array<bool S::*, N>& table) {
  std::uint32_t w = 0;
  for (std::size_t i = 0; i < N; ++i)
    if (table[i] && s.*table[i]) w |= std::uint32_t{1} << i;
  return w;
}
template <class S, std::size_t N>
void unpack_bits(S& s, std::uint32_t w, const std::array<bool S::*, N>& table) {
  for (std::size_t i = 0; i < N; ++i)
    if (table[i]) s.*table[i] = (w >> i) & 1U;
}

// The status bits instance 140 carries: byte 0 and byte 1 bits 0-1.
constexpr std::uint32_t k140StatusMask = 0x03FF;

}  // namespace

std::uint32_t ExtOutputBits::pack() const { return pack_bits(*this, kExtOutBits); }
ExtOutputBits ExtOutputBits::unpack(std::uint32_t bits) {
  ExtOutputBits b;
  unpack_bits(b, bits, kExtOutBits);
  return b;
}

// ---------------------------------------------------------------- outputs
bool encode(const Output20& v, std::span<std::uint8_t> out) {
  if (out.size() != Output20::kSize) return false;
  out[0] = bit(v.run_fwd, Output20::kRunFwd) | bit(v.fault_reset, Output20::kFaultReset);
  out[1] = 0;
  store_le<std::int16_t>(out, 2, v.speed_ref);
  return true;
}
bool decode(std::span<const std::uint8_t> in, Output20& v) {
  if (in.size() != Output20::kSize) return false;
  v.run_fwd = in[0] & Output20::kRunFwd;
  v.fault_reset = in[0] & Output20::kFaultReset;
  v.speed_ref = load_le<std::int16_t>(in, 2);
  return true;
}

bool encode(const Output21& v, std::span<std::uint8_t> out) {
  if (out.size() != Output21::kSize) return false;
  out[0] = bit(v.run_fwd, Output21::kRunFwd) | bit(v.run_rev, Output21::kRunRev) |
           bit(v.fault_reset, Output21::kFaultReset) | bit(v.net_ctrl, Output21::kNetCtrl) |
           bit(v.net_ref, Output21::kNetRef);
  out[1] = 0;
  store_le<std::int16_t>(out, 2, v.speed_ref);
  return true;
}
bool decode(std::span<const std::uint8_t> in, Output21& v) {
  if (in.size() != Output21::kSize) return false;
  v.run_fwd = in[0] & Output21::kRunFwd;
  v.run_rev = in[0] & Output21::kRunRev;
  v.fault_reset = in[0] & Output21::kFaultReset;
  v.net_ctrl = in[0] & Output21::kNetCtrl;
  v.net_ref = in[0] & Output21::kNetRef;
  v.speed_ref = load_le<std::int16_t>(in, 2);
  return true;
}

bool encode(const ExtOutput& v, std::span<std::uint8_t> out) {
  const std::size_t n = output_size(v.instance);
  if (!is_extended_output(v.instance) || out.size() != n) return false;
  std::fill(out.begin(), out.end(), std::uint8_t{0});
  store_le<std::uint32_t>(out, 0, v.bits.pack());
  store_le<std::int16_t>(out, 4, v.speed_ref2);
  store_le<std::int16_t>(out, 6, v.torque_ref);
  if (n >= 10) {
    out[8] = v.day;
    out[9] = v.month;
  }
  if (n >= 12) {
    out[10] = v.minute;
    out[11] = v.hour;
  }
  for (std::size_t w = 0; 12 + 2 * w + 2 <= n; ++w)
    store_le<std::uint16_t>(out, 12 + 2 * w, v.plc_registers[w]);
  return true;
}
bool decode(std::span<const std::uint8_t> in, ExtOutput& v) {
  const std::size_t n = output_size(v.instance);
  if (!is_extended_output(v.instance) || in.size() != n) return false;
  const std::uint8_t inst = v.instance;
  v = ExtOutput{};
  v.instance = inst;
  v.bits = ExtOutputBits::unpack(load_le<std::uint32_t>(in, 0));
  v.speed_ref2 = load_le<std::int16_t>(in, 4);
  v.torque_ref = load_le<std::int16_t>(in, 6);
  if (n >= 10) {
    v.day = in[8];
    v.month = in[9];
  }
  if (n >= 12) {
    v.minute = in[10];
    v.hour = in[11];
  }
  for (std::size_t w = 0; 12 + 2 * w + 2 <= n; ++w)
    v.plc_registers[w] = load_le<std::uint16_t>(in, 12 + 2 * w);
  return true;
}

// ---------------------------------------------------------------- inputs
bool encode(const Input70& v, std::span<std::uint8_t> out) {
  if (out.size() != Input70::kSize) return false;
  out[0] = bit(v.faulted, Input70::kFaulted) | bit(v.running1, Input70::kRunning1);
  out[1] = 0;
  store_le<std::int16_t>(out, 2, v.speed_actual);
  return true;
}
bool decode(std::span<const std::uint8_t> in, Input70& v) {
  if (in.size() != Input70::kSize) return false;
  v.faulted = in[0] & Input70::kFaulted;
  v.running1 = in[0] & Input70::kRunning1;
  v.speed_actual = load_le<std::int16_t>(in, 2);
  return true;
}

bool encode(const Input71& v, std::span<std::uint8_t> out) {
  if (out.size() != Input71::kSize) return false;
  out[0] = bit(v.faulted, Input71::kFaulted) | bit(v.warning, Input71::kWarning) |
           bit(v.running1, Input71::kRunning1) | bit(v.running2, Input71::kRunning2) |
           bit(v.ready, Input71::kReady) | bit(v.ctrl_from_net, Input71::kCtrlFromNet) |
           bit(v.ref_from_net, Input71::kRefFromNet) | bit(v.at_reference, Input71::kAtReference);
  out[1] = static_cast<std::uint8_t>(v.state);
  store_le<std::int16_t>(out, 2, v.speed_actual);
  return true;
}
bool decode(std::span<const std::uint8_t> in, Input71& v) {
  if (in.size() != Input71::kSize) return false;
  v.faulted = in[0] & Input71::kFaulted;
  v.warning = in[0] & Input71::kWarning;
  v.running1 = in[0] & Input71::kRunning1;
  v.running2 = in[0] & Input71::kRunning2;
  v.ready = in[0] & Input71::kReady;
  v.ctrl_from_net = in[0] & Input71::kCtrlFromNet;
  v.ref_from_net = in[0] & Input71::kRefFromNet;
  v.at_reference = in[0] & Input71::kAtReference;
  v.state = static_cast<DriveState>(in[1]);
  v.speed_actual = load_le<std::int16_t>(in, 2);
  return true;
}

bool encode(const ExtInput& v, std::span<std::uint8_t> out) {
  const std::size_t n = input_size(v.instance);
  if (v.instance < 120 || v.instance > 132 || out.size() != n) return false;
  std::fill(out.begin(), out.end(), std::uint8_t{0});
  store_le<std::uint16_t>(out, 0, static_cast<std::uint16_t>(pack_bits(v.status, kStatusBits)));
  store_le<std::uint32_t>(out, 2, v.faults);
  store_le<std::uint16_t>(out, 6, static_cast<std::uint16_t>(pack_bits(v.detect, kDetectBits)));
  const std::array<std::uint16_t, 10> words = {
      static_cast<std::uint16_t>(v.speed_actual2),
      static_cast<std::uint16_t>(v.arc_out),
      v.motor_current,
      static_cast<std::uint16_t>(v.torque_command),
      v.dc_voltage,
      v.output_voltage,
      v.output_frequency,
      v.ol_precounter,
      static_cast<std::uint16_t>(v.motor_temperature),
      v.motor_flux,
  };
  for (std::size_t w = 0; w < words.size() && 8 + 2 * w + 2 <= n; ++w)
    store_le<std::uint16_t>(out, 8 + 2 * w, words[w]);
  for (std::size_t w = 0; 28 + 2 * w + 2 <= n; ++w)
    store_le<std::uint16_t>(out, 28 + 2 * w, v.plc_registers[w]);
  return true;
}
bool decode(std::span<const std::uint8_t> in, ExtInput& v) {
  const std::size_t n = in.size();
  std::uint8_t inst = 0;
  for (std::uint8_t i = 120; i <= 132; ++i)
    if (input_size(i) == n) inst = i;
  if (inst == 0) return false;
  v = ExtInput{};
  v.instance = inst;
  unpack_bits(v.status, load_le<std::uint16_t>(in, 0), kStatusBits);
  v.faults = load_le<std::uint32_t>(in, 2);
  unpack_bits(v.detect, load_le<std::uint16_t>(in, 6), kDetectBits);
  std::array<std::uint16_t, 10> words{};
  for (std::size_t w = 0; w < words.size() && 8 + 2 * w + 2 <= n; ++w)
    words[w] = load_le<std::uint16_t>(in, 8 + 2 * w);
  v.speed_actual2 = static_cast<std::int16_t>(words[0]);
  v.arc_out = static_cast<std::int16_t>(words[1]);
  v.motor_current = words[2];
  v.torque_command = static_cast<std::int16_t>(words[3]);
  v.dc_voltage = words[4];
  v.output_voltage = words[5];
  v.output_frequency = words[6];
  v.ol_precounter = words[7];
  v.motor_temperature = static_cast<std::int16_t>(words[8]);
  v.motor_flux = words[9];
  for (std::size_t w = 0; 28 + 2 * w + 2 <= n; ++w)
    v.plc_registers[w] = load_le<std::uint16_t>(in, 28 + 2 * w);
  return true;
}

bool encode(const Input140& v, std::span<std::uint8_t> out, MonitorByteOrder order) {
  if (out.size() != Input140::kSize) return false;
  const std::uint32_t st = pack_bits(v.status, kStatusBits) & k140StatusMask;
  out[0] = static_cast<std::uint8_t>(st);
  out[1] = static_cast<std::uint8_t>((st >> 8) | ((v.protect_code & 0x3F) << 2));
  store_le<std::uint16_t>(out, 2, v.monitor[0]);
  for (std::size_t i = 1; i < 3; ++i) {
    if (order == MonitorByteOrder::LittleEndian)
      store_le<std::uint16_t>(out, 2 + 2 * i, v.monitor[i]);
    else
      io::store_be<std::uint16_t>(out, 2 + 2 * i, v.monitor[i]);
  }
  return true;
}
bool decode(std::span<const std::uint8_t> in, Input140& v, MonitorByteOrder order) {
  if (in.size() != Input140::kSize) return false;
  v = Input140{};
  unpack_bits(v.status, (std::uint32_t{in[0]} | (std::uint32_t{in[1]} << 8)) & k140StatusMask,
              kStatusBits);
  v.protect_code = static_cast<std::uint8_t>(in[1] >> 2);
  v.monitor[0] = load_le<std::uint16_t>(in, 2);
  for (std::size_t i = 1; i < 3; ++i)
    v.monitor[i] = order == MonitorByteOrder::LittleEndian
                       ? load_le<std::uint16_t>(in, 2 + 2 * i)
                       : io::load_be<std::uint16_t>(in, 2 + 2 * i);
  return true;
}

std::array<std::uint8_t, 3> monitor_selection(unsigned j12) {
  unsigned k = j12;
  for (std::uint8_t a = 1; a <= 8; ++a)
    for (std::uint8_t b = a + 1; b <= 9; ++b)
      for (std::uint8_t c = b + 1; c <= 10; ++c) {
        if (k == 0) return {a, b, c};
        --k;
      }
  return {0, 0, 0};
}

}  // namespace plc::acdrive

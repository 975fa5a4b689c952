// Registers the simulated VF66B as device model "vf66b" and reads its
// `params:` from the cell config (keys: vf66b_model.hpp). Ranges are the
// keypad ranges of Tables 4.1/4.3 (§9); an unknown key is an error.
#include <chrono>
#include <string>

#include "plc/io/device_model.hpp"
#include "vf66b/vf66b_model.hpp"

namespace plc::sim {

Vf66bConfig vf66b_config_from(const io::ModelParams& p) {
  using std::chrono::hours;
  Vf66bConfig c;
  c.j09 = static_cast<unsigned>(p.get_int("j09", c.j09, 0, acdrive::kMaxJ09));
  // [reading] §13.4 item 5: J-10 up to 15 (Table 6.1 defines 11..15).
  c.j10 = static_cast<unsigned>(p.get_int("j10", c.j10, 0, acdrive::kMaxJ10));
  // [reading] §13.4 item 4: the keypad range -126..127 of Table 4.1.
  c.j11 = static_cast<int>(p.get_int("j11", c.j11, -126, 127));
  c.j12 = static_cast<unsigned>(p.get_int("j12", c.j12, 0, 119));
  c.j14 = static_cast<unsigned>(p.get_int("j14", c.j14, 0, 1));
  c.b09 = static_cast<unsigned>(p.get_int("b09", c.b09, 0, 2));
  c.b10 = static_cast<unsigned>(p.get_int("b10", c.b10, 0, 7));
  c.b11 = static_cast<unsigned>(p.get_int("b11", c.b11, 0, 3));
  c.i00 = p.get_bool("i00", c.i00);
  const std::string mode = p.get_string("mode", "im_vector");
  if (mode == "vf") {
    c.mode = Vf66bMode::Vf;
  } else if (mode == "im_vector") {
    c.mode = Vf66bMode::ImVector;
  } else if (mode == "ed_vector") {
    c.mode = Vf66bMode::EdVector;
  } else {
    throw io::ParamError("mode", "mode must be vf, im_vector or ed_vector, not '" + mode + "'");
  }
  c.poles = static_cast<unsigned>(p.get_int("poles", c.poles, 2, 64));
  if (c.poles % 2) throw io::ParamError("poles", "poles (A-06) must be even");
  c.motor_type = static_cast<std::uint8_t>(p.get_int("motor_type", c.motor_type, 0, 10));
  c.rated_current =
      static_cast<std::uint16_t>(p.get_int("rated_current", c.rated_current, 0, 65535));
  c.rated_voltage =
      static_cast<std::uint16_t>(p.get_int("rated_voltage", c.rated_voltage, 0, 65535));
  c.voltage_class = static_cast<unsigned>(p.get_int("voltage_class", c.voltage_class, 200, 400));
  if (c.voltage_class != 200 && c.voltage_class != 400)
    throw io::ParamError("voltage_class", "voltage_class must be 200 or 400");
  c.top_speed_rpm = p.get_double("top_speed_rpm", c.top_speed_rpm, 1, 100000);
  auto seconds_of = [&](const char* key, double def) {
    const TIME t =
        p.get_time(key, std::chrono::duration_cast<TIME>(std::chrono::duration<double>(def)),
                   TIME(0), hours(1));
    return std::chrono::duration<double>(t).count();
  };
  c.accel_time_s = seconds_of("accel_time", c.accel_time_s);
  c.decel_time_s = seconds_of("decel_time", c.decel_time_s);
  c.coast_time_s = seconds_of("coast_time", c.coast_time_s);
  c.local_speed_rpm = p.get_double("local_speed_rpm", c.local_speed_rpm, -100000, 100000);
  c.startup_time = p.get_time("startup_time", c.startup_time, TIME(0), hours(1));
  c.st_f = p.get_bool("st_f", c.st_f);
  c.main_power = p.get_bool("main_power", c.main_power);
  const std::string loss = p.get_string("comm_loss", "trip");
  if (loss == "trip") {
    c.comm_loss_trip = true;
  } else if (loss == "ignore") {
    c.comm_loss_trip = false;
  } else {
    throw io::ParamError("comm_loss", "comm_loss must be trip or ignore, not '" + loss + "'");
  }
  c.restart_after_reset = p.get_bool("restart_after_reset", c.restart_after_reset);
  const std::string order = p.get_string("monitor_order", "little_endian");
  if (order == "little_endian") {
    c.monitor_order = acdrive::MonitorByteOrder::LittleEndian;
  } else if (order == "manual_literal") {
    c.monitor_order = acdrive::MonitorByteOrder::ManualLiteral;
  } else {
    throw io::ParamError("monitor_order", "monitor_order must be little_endian or manual_literal");
  }
  const auto code = p.get_int("fault_code", 0, 0, 32);
  if (code != 0 && (code == 3 || code == 4))
    throw io::ParamError("fault_code", "fault_code must be 1, 2 or 5..32 (Table 6.4)");
  c.fault_code = static_cast<std::uint8_t>(code);
  c.fault_at = p.get_time("fault_at", c.fault_at, TIME(0), hours(24 * 365));
  c.fault_persists = p.get_bool("fault_persists", c.fault_persists);
  p.reject_unknown();
  return c;
}

PLC_REGISTER_DEVICE_MODEL("vf66b", Vf66bModel)

}  // namespace plc::sim

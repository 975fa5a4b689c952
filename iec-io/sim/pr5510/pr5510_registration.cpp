// Registers the simulated PR5510 as device model "pr5510" and reads its
// `params:` from the cell config. Keys (all optional):
//   bus: profibus | devicenet          byte order of bytes 0..3 (spec §3)
//   packed_order: msb_first | cclink   codes 4/5 word order ([AMBIG] 9)
//   seed, full_scale, decimals, division, unit (g|kg|t|lb), overload,
//   zero_range, standstill_range, standstill_time, filter_time, tare_timeout,
//   legal_for_trade, cal_switch_locked, test_value, strict_codes, scale_interface,
//   coarse_rate, fine_rate, discharge_rate, flow_variation, flow_wander,
//   fall_time, valve_time, noise, impact_noise, initial_load
#include "plc/io/device_model.hpp"
#include "pr5510/pr5510_model.hpp"

namespace plc::sim {

Pr5510Config pr5510_config_from(const io::ModelParams& p) {
  Pr5510Config c;
  const std::string bus = p.get_string("bus", "profibus");
  if (bus == "profibus") {
    c.bus = weighing::Bus::Profibus;
  } else if (bus == "devicenet") {
    c.bus = weighing::Bus::DeviceNet;
  } else {
    throw io::ParamError("bus", "bus must be profibus or devicenet, not '" + bus + "'");
  }
  const std::string po = p.get_string("packed_order", "msb_first");
  if (po == "msb_first") {
    c.packed_order = weighing::PackedOrder::MsbFirst;
  } else if (po == "cclink") {
    c.packed_order = weighing::PackedOrder::CcLink;
  } else {
    throw io::ParamError("packed_order", "packed_order must be msb_first or cclink");
  }
  const std::string unit = p.get_string("unit", "kg");
  if (unit == "g") {
    c.unit = weighing::Unit::g;
  } else if (unit == "kg") {
    c.unit = weighing::Unit::kg;
  } else if (unit == "t") {
    c.unit = weighing::Unit::t;
  } else if (unit == "lb") {
    c.unit = weighing::Unit::lb;
  } else {
    throw io::ParamError("unit", "unit must be g, kg, t or lb");
  }
  c.full_scale = p.get_double("full_scale", c.full_scale);
  if (c.full_scale <= 0) throw io::ParamError("full_scale", "full_scale must be > 0");
  c.decimals = static_cast<std::uint8_t>(p.get_int("decimals", c.decimals, 0, 6));
  c.division = static_cast<std::uint8_t>(p.get_int("division", c.division, 1, 255));
  c.overload = p.get_double("overload", c.overload);
  c.zero_range = p.get_double("zero_range", c.zero_range);
  c.standstill_range = p.get_double("standstill_range", c.standstill_range);
  c.standstill_time = p.get_time("standstill_time", c.standstill_time);
  c.filter_time = p.get_time("filter_time", c.filter_time);
  c.tare_timeout = p.get_time("tare_timeout", c.tare_timeout);
  c.legal_for_trade = p.get_bool("legal_for_trade", c.legal_for_trade);
  c.cal_switch_locked = p.get_bool("cal_switch_locked", c.cal_switch_locked);
  c.test_value = p.get_double("test_value", c.test_value);
  c.strict_codes = p.get_bool("strict_codes", c.strict_codes);
  c.scale_interface = p.get_bool("scale_interface", c.scale_interface);
  FillingConfig& f = c.filling;
  f.seed = static_cast<std::uint64_t>(p.get_int("seed", 1, 0));
  f.coarse_rate = p.get_double("coarse_rate", f.coarse_rate);
  f.fine_rate = p.get_double("fine_rate", f.fine_rate);
  f.discharge_rate = p.get_double("discharge_rate", f.discharge_rate);
  f.flow_variation = p.get_double("flow_variation", f.flow_variation);
  f.flow_wander = p.get_double("flow_wander", f.flow_wander);
  f.fall_time_s =
      std::chrono::duration<double>(p.get_time("fall_time", std::chrono::milliseconds(250)))
          .count();
  f.valve_time_s =
      std::chrono::duration<double>(p.get_time("valve_time", std::chrono::milliseconds(30)))
          .count();
  f.noise_kg = p.get_double("noise", f.noise_kg);
  f.impact_noise = p.get_double("impact_noise", f.impact_noise);
  f.initial_load = p.get_double("initial_load", f.initial_load);
  if (f.fall_time_s > 10.0) throw io::ParamError("fall_time", "fall_time must be <= 10 s");
  p.reject_unknown();
  return c;
}

PLC_REGISTER_DEVICE_MODEL("pr5510", Pr5510Model)

}  // namespace plc::sim

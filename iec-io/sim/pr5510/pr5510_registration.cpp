// Registers the simulated PR5510 as device model "pr5510" and reads its
// `params:` from the cell config. Keys (all optional):
//   bus: profibus | devicenet          byte order of bytes 0..3 (spec §3)
//   packed_order: msb_first | cclink   codes 4/5 word order ([AMBIG] 9)
//   seed, full_scale, decimals, division, unit (g|kg|t|lb), overload,
//   zero_range, standstill_range, standstill_time, filter_time, tare_timeout,
//   legal_for_trade, cal_switch_locked, test_value, strict_codes, scale_interface,
//   coarse_rate, fine_rate, discharge_rate, flow_variation, flow_wander,
//   fall_time, valve_time, noise, impact_noise, initial_load
#include <cmath>
#include <cstdint>

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
  // Ranges: weights are DINTs in display digits on the wire (spec §5.2,
  // code 0x0E FSD), so full scale plus overload, and the test value, must fit
  // a DINT at the chosen decimals (checked below); times from 0 to an hour;
  // flow rates to 1000 kg/s.
  using std::chrono::hours;
  using std::chrono::milliseconds;
  using std::chrono::seconds;
  constexpr double kKg = 1e9;  // beyond any scale; the DINT check below is the real bound
  c.full_scale = p.get_double("full_scale", c.full_scale, 1e-6, kKg);
  c.decimals = static_cast<std::uint8_t>(p.get_int("decimals", c.decimals, 0, 6));
  c.division = static_cast<std::uint8_t>(p.get_int("division", c.division, 1, 255));
  c.overload = p.get_double("overload", c.overload, 0, kKg);
  c.zero_range = p.get_double("zero_range", c.zero_range, 0, kKg);
  c.standstill_range = p.get_double("standstill_range", c.standstill_range, 0, 2147483647.0);
  c.standstill_time = p.get_time("standstill_time", c.standstill_time, TIME(0), hours(1));
  c.filter_time = p.get_time("filter_time", c.filter_time, TIME(0), hours(1));
  c.tare_timeout = p.get_time("tare_timeout", c.tare_timeout, TIME(0), hours(1));
  c.legal_for_trade = p.get_bool("legal_for_trade", c.legal_for_trade);
  c.cal_switch_locked = p.get_bool("cal_switch_locked", c.cal_switch_locked);
  c.test_value = p.get_double("test_value", c.test_value, -kKg, kKg);
  c.strict_codes = p.get_bool("strict_codes", c.strict_codes);
  c.scale_interface = p.get_bool("scale_interface", c.scale_interface);
  const double digits_per_kg = std::pow(10.0, c.decimals);
  auto fits_dint = [&](const char* key, double kg) {
    if (std::fabs(kg * digits_per_kg) > 2147483647.0)
      throw io::ParamError(key, std::string(key) + " gives " + std::to_string(kg * digits_per_kg) +
                                    " digits at " + std::to_string(c.decimals) +
                                    " decimals: weights are DINTs (at most 2147483647 digits)");
  };
  fits_dint("full_scale", c.full_scale + c.overload);
  fits_dint("test_value", c.test_value);
  FillingConfig& f = c.filling;
  f.seed = static_cast<std::uint64_t>(p.get_int("seed", 1, 0, INT64_MAX));
  f.coarse_rate = p.get_double("coarse_rate", f.coarse_rate, 0, 1000);
  f.fine_rate = p.get_double("fine_rate", f.fine_rate, 0, 1000);
  f.discharge_rate = p.get_double("discharge_rate", f.discharge_rate, 0, 1000);
  f.flow_variation = p.get_double("flow_variation", f.flow_variation, 0, 1);
  f.flow_wander = p.get_double("flow_wander", f.flow_wander, 0, 1);
  f.fall_time_s = std::chrono::duration<double>(
                      p.get_time("fall_time", milliseconds(250), TIME(0), seconds(10)))
                      .count();
  f.valve_time_s = std::chrono::duration<double>(
                       p.get_time("valve_time", milliseconds(30), TIME(0), seconds(10)))
                       .count();
  f.noise_kg = p.get_double("noise", f.noise_kg, 0, 1000);
  f.impact_noise = p.get_double("impact_noise", f.impact_noise, 0, 1000);
  f.initial_load = p.get_double("initial_load", f.initial_load, -kKg, kKg);
  p.reject_unknown();
  return c;
}

PLC_REGISTER_DEVICE_MODEL("pr5510", Pr5510Model)

}  // namespace plc::sim

#include "plc/profinet/controller/device_params.hpp"

#include "plc/profinet/description/description_params.hpp"

namespace plc::profinet {

namespace {
constexpr const char* kControllerKeys[] = {"set_name",    "set_ip",         "mac",
                                           "record_slot", "record_subslot", "record_api"};
}

ControllerDevice device_from_params(const std::string& name, const std::string& model,
                                    const io::ModelParams& p) {
  ControllerDevice d;
  d.name = name;
  d.desc = description_from_params(model, p);
  d.set_name = p.get_bool("set_name", false);
  d.set_ip = p.get_bool("set_ip", false);
  const std::string mac = p.get_string("mac", "");
  if (!mac.empty()) {
    const auto m = parse_mac(mac);
    if (!m) throw io::ParamError("mac", "'" + mac + "' is not a MAC address (02:00:00:00:00:05)");
    d.mac = *m;
  }
  if (d.set_name && mac.empty())
    throw io::ParamError("set_name",
                         "set_name: true needs the device's mac (the device to give the name)");
  if (p.has("record_slot") || p.has("record_subslot") || p.has("record_api")) {
    d.record_target_given = true;
    d.record_slot = static_cast<std::uint16_t>(p.get_int("record_slot", 1, 0, 0x7FFF));
    d.record_subslot = static_cast<std::uint16_t>(p.get_int("record_subslot", 1, 1, 0xFFFF));
    d.record_api = static_cast<std::uint32_t>(p.get_int("record_api", 0, 0, 0xFFFFFFFF));
  }
  return d;
}

io::ModelParams device_model_params(const io::ModelParams& params) {
  const io::ModelParams rest = model_params_of(params);
  io::ModelParams out;
  out.set_folder(params.folder());
  for (const auto& [k, v] : rest.values()) {
    bool ours = false;
    for (const char* c : kControllerKeys) ours = ours || k == c;
    if (!ours) out.set(k, v);
  }
  return out;
}

}  // namespace plc::profinet

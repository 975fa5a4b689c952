// A `profinet` plugin device from the cell config: the description
// (description_params.hpp: model, station_name, ip, slots, records) and the
// controller's own keys:
//   set_name: true, mac: 02:00:00:00:00:05   DCP Set NameOfStation (the
//                                             device with that MAC) first
//   set_ip: true                              DCP Set IP (ip/netmask/gateway)
//   record_slot, record_subslot, record_api  where the FBs' records go
//                                             (default: the IO submodule)
#pragma once

#include <string>

#include "plc/io/model_params.hpp"
#include "plc/profinet/controller/controller.hpp"

namespace plc::profinet {

// Throws io::ParamError naming the key. Marks the keys it reads used.
ControllerDevice device_from_params(const std::string& name, const std::string& model,
                                    const io::ModelParams& params);
// The params the device's own model gets: everything but the description's
// and the controller's keys.
io::ModelParams device_model_params(const io::ModelParams& params);

}  // namespace plc::profinet

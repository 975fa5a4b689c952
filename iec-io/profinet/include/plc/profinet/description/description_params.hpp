// The device description in the cell config: the `model:` and `params:` of a
// device of the `profinet` plugin (docs/config.md, "PROFINET devices").
//
//   model: hiwin_e1 | nord_profisafe    built-in description (+ its params,
//                                       e.g. telegram: 111)
//   model: gsdml                        gsdml: FILE, gsdml_dap: ID-or-name,
//                                       gsdml_modules: "1=ID; 2=ID"
//   model: generic                      inline slots:
//     dap: "module=0x1 submodule=0x1 interface=0x8000 port=0x8001"
//     submodule.1.1: "module=0x111 submodule=0x111 api=0x3A00 in=24 out=24"
//   every model:
//     station_name: NAME (required), ip: A.B.C.D (required),
//     netmask, gateway, vendor_id, device_id, instance (override),
//     min_device_interval: 1ms,
//     records.S.SS: "INDEX=HEXBYTES; INDEX=HEXBYTES"  (start-up records of
//                                       submodule S/SS, written in order)
#pragma once

#include <string>

#include "plc/io/model_params.hpp"
#include "plc/profinet/description/device_description.hpp"

namespace plc::profinet {

// Throws io::ParamError naming the offending key. Reads only the keys above
// (marking them used); the caller calls params.reject_unknown() after its
// own keys.
DeviceDescription description_from_params(const std::string& model, const io::ModelParams& params);

// The params a device model hosted for this description gets: everything but
// the keys above (pndevsim hands the rest to the model, e.g. telegram,
// dip_address). `telegram` is both: it shapes the description and the model.
[[nodiscard]] io::ModelParams model_params_of(const io::ModelParams& params);

}  // namespace plc::profinet

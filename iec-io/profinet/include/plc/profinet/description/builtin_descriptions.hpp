// Built-in descriptions of the devices we simulate. Their ident numbers are
// ours (the manuals give none), documented in iec-io/profinet/README.md and
// written as GSDML in iec-io/profinet/gsdml/; a test checks that both agree.
//
//   hiwin_e1        HIWIN E1 servo: DAP, and in slot 1 subslot 1 (API 0x3A00)
//                   the telegram submodule of `telegram` (3, 9 or 111,
//                   default 111, hiwin-e1-profinet.md §1.2, §3.1 Table 3.2.1)
//   nord_profisafe  NORD SK TU4-PNS / SK CU4-PNS: DAP, and in slot 1 the SAFE
//                   submodule, 8 bytes each way (nord-profisafe.md §2.1, §3.1)
#pragma once

#include <string>
#include <vector>

#include "plc/io/model_params.hpp"
#include "plc/profinet/description/device_description.hpp"

namespace plc::profinet {

// Our vendor ID for both (0x0000 is no vendor's; see the README).
inline constexpr std::uint16_t kOurVendorId = 0x0FFF;
inline constexpr std::uint16_t kHiwinE1DeviceId = 0x0E01;
inline constexpr std::uint16_t kNordProfisafeDeviceId = 0x0280;

[[nodiscard]] std::vector<std::string> builtin_models();
[[nodiscard]] bool is_builtin_model(const std::string& model);

// The description for `model` with the params that shape it (hiwin_e1:
// `telegram`). Station name and IP are left empty (description_params.hpp
// fills them). Throws io::ParamError (unknown model, bad telegram).
DeviceDescription builtin_description(const std::string& model, const io::ModelParams& params);

}  // namespace plc::profinet

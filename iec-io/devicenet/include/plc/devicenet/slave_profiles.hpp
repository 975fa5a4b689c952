// Identities and assembly instances of the devices we simulate as slaves.
#pragma once

#include <optional>
#include <string>

#include "plc/devicenet/slave.hpp"

namespace plc::devicenet {

// "pr1721_34": the PR5510's DeviceNet card, from its EDS
// (sartorius-pr1721.md §2.3): vendor 560, product type 12, product code
// 1713, revision 1.3, "System Weighing Controller"; polled I/O of 8 bytes
// each way, input assembly 100 (0x64), output assembly 150 (0x96).
// "dnet66z": the VF66B's DeviceNet card (toyo-vf66-devicenet.md §1.1):
// device type 0x02, assemblies 21/71; identity values are placeholders (the
// manual gives none).
// nullopt for an unknown name.
std::optional<SlaveConfig> slave_profile(const std::string& name);

}  // namespace plc::devicenet

#include "plc/devicenet/slave_profiles.hpp"

namespace plc::devicenet {

std::optional<SlaveConfig> slave_profile(const std::string& name) {
  SlaveConfig c;
  if (name == "pr1721_34") {
    c.identity.vendor = 560;
    c.identity.device_type = 12;
    c.identity.product_code = 1713;
    c.identity.major_rev = 1;
    c.identity.minor_rev = 3;
    c.identity.product_name = "System Weighing Controller";
    c.input_assembly = 100;
    c.output_assembly = 150;
    return c;
  }
  if (name == "dnet66z") {
    // The VF66B's DNET66-Z card: device type 0x02 (AC drive, §1.1). The
    // manual gives no vendor ID, product code, revision or name (§1.1,
    // §13.4 item 12): ours are placeholders, set `vendor:` etc. to a real
    // card's values. Assemblies: the AC Drive profile default 21/71 (J-09 =
    // J-10 = 1); dnslave takes the model's j09/j10 instead (§7.2).
    c.identity.vendor = 0;
    c.identity.device_type = 0x02;
    c.identity.product_code = 0;
    c.identity.major_rev = 1;
    c.identity.minor_rev = 1;
    c.identity.product_name = "VF66B DNET66-Z (simulated)";
    c.input_assembly = 71;
    c.output_assembly = 21;
    return c;
  }
  return std::nullopt;
}

}  // namespace plc::devicenet

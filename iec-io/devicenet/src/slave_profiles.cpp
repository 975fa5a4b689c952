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
  return std::nullopt;
}

}  // namespace plc::devicenet

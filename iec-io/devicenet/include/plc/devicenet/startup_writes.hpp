// The `startup:` parameter of a scan-list entry: attribute writes the
// scanner sends (Set_Attribute_Single) after allocation, before polling.
//   startup: "0x2A/1/22=03; 0x29/1/5=01"     CLASS/INSTANCE/ATTRIBUTE=HEX BYTES
// (little-endian data, as on the wire: 0x2A/1/22=03 sets SpeedScale to 3).
#pragma once

#include <string>
#include <vector>

#include "plc/devicenet/scanner.hpp"

namespace plc::devicenet {

// Throws io::ParamError("startup", ...) naming the bad item.
std::vector<AttributeWrite> parse_startup_writes(const std::string& text);

}  // namespace plc::devicenet

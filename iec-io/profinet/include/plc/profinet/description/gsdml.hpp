// Device descriptions from a GSDML file (the PROFINET device description
// XML that vendors ship; GSDML V2.x), parsed with libxml2.
//
// Taken from the file: VendorID, DeviceID (DeviceIdentity); the DAP's
// ModuleIdentNumber, MinDeviceInterval, its virtual submodule and its
// interface/port submodule idents (SystemDefinedSubmoduleList); per selected
// module its ModuleIdentNumber and every VirtualSubmoduleItem (subslot from
// FixedInSubslots, else 1, 2, ...; API; SubmoduleIdentNumber; IO data
// lengths from the DataItems; ParameterRecordDataItems with their default
// values as start-up records).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "plc/profinet/description/device_description.hpp"

namespace plc::profinet {

// "FILE:LINE: what" (LINE 0 when the file could not be read or parsed as a
// whole).
struct GsdmlError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct GsdmlSelection {
  // DeviceAccessPointItem by its ID attribute or its name (the text of its
  // Name TextId); empty: the first DAP in the file.
  std::string dap;
  struct Slot {
    std::uint16_t slot = 1;
    std::string module;  // ModuleItem by ID or name
  };
  std::vector<Slot> modules;
};

// Throws GsdmlError.
DeviceDescription load_gsdml(const std::string& path, const GsdmlSelection& selection);

// "1=ID_Mod_Tel111; 2=DIG-IO": slot = module, ';'-separated. Throws
// std::invalid_argument saying what is wrong.
std::vector<GsdmlSelection::Slot> parse_gsdml_modules(const std::string& text);

}  // namespace plc::profinet

// The Connect request the controller sends for a DeviceDescription, and the
// IO data layout that follows from it (connect_plan.cpp).
#pragma once

#include <vector>

#include "plc/profinet/controller/controller.hpp"
#include "plc/profinet/wire/blocks.hpp"
#include "plc/profinet/wire/cyclic.hpp"

namespace plc::profinet {

// What one Connect asks for, and where the user data of each IO submodule
// lies in the process image (the device's %I / %Q bytes are its IO
// submodules' data, concatenated in slot/subslot order).
struct ConnectPlan {
  ConnectRequest request;
  CyclicLayout layout;
  struct UserData {
    IoDataObject object;      // in the C_SDU
    std::size_t user_offset;  // in the device's input or output bytes
  };
  std::vector<UserData> inputs, outputs;
};

// Ident numbers, lengths and every parameter chosen so that a p-net device
// accepts them (fieldbus-masters.md §1 item 2; test_controller_connect
// checks each rule). Throws std::invalid_argument if the description cannot
// be laid out in one RT_CLASS_1 frame.
ConnectPlan plan_connect(const ControllerConfig& cfg, const DeviceDescription& desc,
                         const Mac& controller_mac, const Uuid& ar_uuid, std::uint16_t session_key,
                         std::uint16_t input_frame_id);

// The CMInitiatorObjectUUID of our controller (the ApplicationReady's
// object UUID).
Uuid controller_object_uuid(const ControllerConfig& cfg);

}  // namespace plc::profinet

// A simulated slave's identity from its GSD: Ident_Number, the modules'
// Cfg bytes and Max_Module (a modular station accepts any combination that
// adds up to its I/O), Freeze/Sync support, User_Prm_Data_Len.
#pragma once

#include "plc/profibus/gsd/gsd.hpp"
#include "plc/profibus/slave/dp_slave.hpp"

namespace plc::profibus::slave {

// `io_bytes` each way (the PR5510 menu's "I/Os": 8, 16, 24, 32, 64). A
// compact station (Modular_Station = 0) takes exactly its one module.
SlaveConfig slave_config_from_gsd(const gsd::Gsd& g, std::uint8_t address, std::size_t in_bytes,
                                  std::size_t out_bytes);

}  // namespace plc::profibus::slave

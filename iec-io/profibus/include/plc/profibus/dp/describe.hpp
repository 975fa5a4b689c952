// One line of text for a telegram, decoded down to the DP service (the
// text capture and the logs): "SD2 2->8 SRD_high FCB=1 FCV=1 Set_Prm: ...".
#pragma once

#include <string>

#include "plc/profibus/fdl/telegram.hpp"

namespace plc::profibus::dp {

std::string describe(const fdl::Telegram& t);

}  // namespace plc::profibus::dp

#include "tank_cycle.hpp"

namespace demo {
PLC_REGISTER_PROGRAM(TankCycle)
}

#include "retain_programs.hpp"

namespace retaintest {
PLC_REGISTER_PROGRAM(RetainProbe)
PLC_REGISTER_PROGRAM(RetainProbeV2)
PLC_REGISTER_PROGRAM(RetainedOutput)
}  // namespace retaintest

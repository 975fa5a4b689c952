#include "plc/fb/acdrive/protect_codes.hpp"

#include <array>

namespace plc::acdrive {

const char* protect_code_text(unsigned code) {
  // Table 6.4 (§7.8), index = code.
  static constexpr std::array<const char*, kMaxProtectCode + 1> kText = {
      "No fault / protection",
      "Overcurrent protection",
      "IGBT protection",
      "",
      "",
      "GAC error (gate board error)",
      "DC-link overvoltage",
      "Overload protection",
      "DCCT error (current sensor error)",
      "Start stall",
      "Overspeed protection",
      "Overfrequency protection",
      "Undervoltage (power failure)",
      "Overtorque protection",
      "Unit overheat",
      "Memory (storage) error",
      "Option error",
      "Sensorless start error",
      "Communication timeout error",
      "Speed control error",
      "Motor overheat",
      "Charging resistor overheat",
      "FCL operation",
      "Setting error",
      "Phase loss",
      "CPU abnormal processing",
      "Fan failure",
      "PG error",
      "Sensor error",
      "External fault 1",
      "External fault 2",
      "External fault 3",
      "External fault 4",
  };
  return code <= kMaxProtectCode ? kText[code] : "";
}

}  // namespace plc::acdrive

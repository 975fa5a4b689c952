#include "test_programs.hpp"

#include <chrono>
#include <stdexcept>

namespace plctest {

void Spinner::cycle(const ScanContext&) {
  ++scans;
  out = INT(1234);
  lamp = true;
  if (spin) {
    // Deliberately burns wall time: the watchdog measures real scan time.
    const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(spin_us);
    while (std::chrono::steady_clock::now() < until) {
    }
  }
}

void Thrower::cycle(const ScanContext&) {
  out = true;
  if (fire) throw std::runtime_error("boom");
}

PLC_REGISTER_PROGRAM(ReleaseLog)
PLC_REGISTER_PROGRAM(Spinner)
PLC_REGISTER_PROGRAM(BitWriter)
PLC_REGISTER_PROGRAM(LoopCounter)
PLC_REGISTER_PROGRAM(Thrower)
PLC_REGISTER_PROGRAM(Shapes)

}  // namespace plctest

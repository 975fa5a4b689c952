// `comm_watchdog`: a device with a communication watchdog, as fieldbus
// devices have (PROFINET's data-hold time, a DeviceNet connection's expected
// packet rate): if it is not exchanged with for longer than `timeout`, it
// trips and stays tripped until power-cycled.
//
// PLC -> device (2 bytes): WORD, echoed.
// device -> PLC (4 bytes): WORD echo; WORD status: bit 0 = communication ok,
//   bit 1 = watchdog tripped (latched).
// It also counts its exchanges, so a test can see the bus kept running.
#include "plc/io/comm_watchdog_probe.hpp"

#include "plc/io/byte_order.hpp"
#include "plc/io/device_model.hpp"

namespace plc::io {

CommWatchdogProbe::CommWatchdogProbe(const ModelParams& p)
    : timeout_(p.get_time("timeout", std::chrono::milliseconds(100), std::chrono::microseconds(1),
                          std::chrono::hours(24))) {
  p.reject_unknown();
}

void CommWatchdogProbe::step(TIME, TIME dt, std::span<const std::uint8_t> from_plc,
                             std::span<std::uint8_t> to_plc) {
  exchanges_.fetch_add(1, std::memory_order_relaxed);
  if (dt.count() > longest_gap_ns_.load(std::memory_order_relaxed))
    longest_gap_ns_.store(dt.count(), std::memory_order_relaxed);
  if (dt > timeout_) tripped_.store(true, std::memory_order_relaxed);
  store_be<std::uint16_t>(to_plc, 0, load_be<std::uint16_t>(from_plc, 0));
  store_be<std::uint16_t>(to_plc, 2, static_cast<std::uint16_t>((tripped() ? 2U : 1U)));
}

void CommWatchdogProbe::power_cycle() {
  tripped_.store(false, std::memory_order_relaxed);
  longest_gap_ns_.store(0, std::memory_order_relaxed);
}

PLC_REGISTER_DEVICE_MODEL("comm_watchdog", CommWatchdogProbe)

}  // namespace plc::io

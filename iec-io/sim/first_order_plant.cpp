// `first_order`: a first-order lag plant (a heated tank, a level, a speed
// loop) with an analog actuator and an analog sensor, scaled like an S7
// analog module: 0..27648 = 0..100 %.
//
// PLC -> device (2 bytes): INT actuator command, big-endian, 0..27648.
// device -> PLC (4 bytes): INT measured value, big-endian, 0..27648 of
//   `range`; WORD status: bit 0 = ready, bit 1 = high alarm (value >= `high`).
//
// dy/dt = (gain * u - y) / tau, integrated exactly for each step (so the
// result does not depend on the step size beyond rounding).
//
// Parameters: tau (1us .. 1d, default 2s), gain, initial and high (in units
// of the full range, -1000 .. 1000; defaults 1, 0, 0.9).
#include <algorithm>
#include <cmath>

#include "plc/io/byte_order.hpp"
#include "plc/io/device_model.hpp"

namespace plc::io {
namespace {

class FirstOrderPlant final : public DeviceModel {
 public:
  explicit FirstOrderPlant(const ModelParams& p)
      : tau_s_(std::chrono::duration<double>(p.get_time("tau", std::chrono::seconds(2),
                                                        std::chrono::microseconds(1),
                                                        std::chrono::hours(24)))
                   .count()),
        gain_(p.get_double("gain", 1.0, -kRange, kRange)),
        y_(p.get_double("initial", 0.0, -kRange, kRange)),
        high_(p.get_double("high", 0.9, -kRange, kRange)) {
    p.reject_unknown();
  }
  std::size_t input_size() const override { return 4; }
  std::size_t output_size() const override { return 2; }

  void step(TIME, TIME dt, std::span<const std::uint8_t> from_plc,
            std::span<std::uint8_t> to_plc) override {
    const double u =
        std::clamp(load_be<std::int16_t>(from_plc, 0), std::int16_t{0}, std::int16_t{27648}) /
        27648.0;
    const double h = std::chrono::duration<double>(dt).count();
    const double target = gain_ * u;
    y_ = target + (y_ - target) * std::exp(-h / tau_s_);
    const double y = std::clamp(y_, 0.0, 1.0);
    store_be<std::int16_t>(to_plc, 0, static_cast<std::int16_t>(std::lround(y * 27648.0)));
    std::uint16_t status = 1;
    if (y_ >= high_) status |= 2;
    store_be<std::uint16_t>(to_plc, 2, status);
  }

 private:
  static constexpr double kRange = 1000;  // x full range: far beyond any plant, finite
  double tau_s_, gain_, y_, high_;
};

// `loopback`: echoes the PLC's output bytes back as inputs (size bytes each
// way), one step later. The simplest device for exercising the whole path.
class Loopback final : public DeviceModel {
 public:
  explicit Loopback(const ModelParams& p)
      : size_(static_cast<std::size_t>(p.get_int("size", 8, 1, 1440))) {
    p.reject_unknown();
  }
  std::size_t input_size() const override { return size_; }
  std::size_t output_size() const override { return size_; }
  void step(TIME, TIME, std::span<const std::uint8_t> from_plc,
            std::span<std::uint8_t> to_plc) override {
    std::copy(from_plc.begin(), from_plc.end(), to_plc.begin());
  }

 private:
  std::size_t size_;
};

}  // namespace

PLC_REGISTER_DEVICE_MODEL("first_order", FirstOrderPlant)
PLC_REGISTER_DEVICE_MODEL("loopback", Loopback)

}  // namespace plc::io

// PROFIdrive sign-of-life in STW2/ZSW2 bits 12-15 (spec §4.3, §4.6, §10.1).
//
// [STD] The counter runs 1..15 and wraps to 1; 0 is skipped. Monitoring
// starts once the partner's counter is first non-zero; each cycle in which
// the value is not the previous value + 1 is a failure. More than
// `tolerance` consecutive failures (PNU 925, default 5) is a loss of
// sign-of-life. Used on both sides: the simulated drive watches STW2, the
// PLC-side axis watches ZSW2.
#pragma once

#include <cstdint>

namespace plc::drive {

constexpr std::uint8_t next_sign_of_life(std::uint8_t v) {
  return static_cast<std::uint8_t>(v >= 15 ? 1 : v + 1);
}

class SignOfLifeMonitor {
 public:
  // Feed the partner's counter once per cycle. Returns true while healthy.
  bool update(std::uint8_t value, std::uint16_t tolerance) {
    value &= 0xF;
    if (!started_) {
      if (value != 0) {
        started_ = true;
        last_ = value;
      }
      return !lost_;
    }
    if (value == next_sign_of_life(last_)) {
      failures_ = 0;
    } else if (++failures_ > tolerance) {
      lost_ = true;
    }
    last_ = value;
    return !lost_;
  }
  // Restart monitoring (after a fault acknowledge or a reconnect).
  void reset() { *this = SignOfLifeMonitor{}; }

  [[nodiscard]] bool lost() const { return lost_; }
  [[nodiscard]] bool started() const { return started_; }
  [[nodiscard]] std::uint16_t failures() const { return failures_; }

 private:
  std::uint16_t failures_ = 0;
  std::uint8_t last_ = 0;
  bool started_ = false;
  bool lost_ = false;
};

}  // namespace plc::drive

// The NORD safe speed/position monitoring functions SLS, SSR, SDI-P, SDI-N,
// SOS and SSM (spec nord-profisafe.md §1.5, §8.3 "Safety logic each cycle"),
// evaluated against speed and position from the simulated drive.
//
// * A function is monitored when P820 enables it AND the host requests it;
//   monitoring starts after the activation time P821 and stops at once when
//   the request drops.
// * The reaction time P822 is an up/down integrating counter: it counts up
//   while the limit is violated and down while it is not; the error is raised
//   when it reaches P822 (immediately for 0). SOS has no reaction time.
// * SDI counts movement in the forbidden direction since monitoring started
//   and trips above P824; SOS trips when the position leaves the P824 window
//   around the position at monitoring start.
// * SSM: status bit only, 1 when |speed| <= P823[-07] (spec [AMBIG] reading).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "plc/sim/nord_iparams.hpp"
#include "plc/types.hpp"

namespace plc::sim {

class NordSafetyFunctions {
 public:
  enum Fn : int { kSls = 0, kSsr = 1, kSdiP = 2, kSdiN = 3, kSos = 4, kCount = 5 };

  struct Request {
    std::array<bool, kCount> on{};  // host request bits (already 0 when passivated)
    std::uint8_t sls_level = 0;     // 0..3
  };

  explicit NordSafetyFunctions(const NordIParams& ip)
      : ip_(ip), ssm_max_(static_cast<double>(ip.p823[6])) {
    for (int fn = 0; fn < kCount; ++fn)
      if (ip_.p820[fn] == 1) enabled_ |= static_cast<std::uint8_t>(1u << fn);
  }

  // Advance by dt; position in encoder increments. Inline for a device
  // with no function enabled (P820 all 0, the usual one), where only SSM is
  // evaluated and the request is not read.
  void step(TIME now, TIME dt, const Request& rq, double speed_rpm, double position_inc) {
    if (enabled_ == 0 && idle_) {
      status_[kCount] = std::abs(speed_rpm) <= ssm_max_;
      return;
    }
    step_functions(now, dt, rq, speed_rpm, position_inc);
  }
  // P820 enables at least one function (else step() does not read rq).
  [[nodiscard]] bool any_enabled() const { return enabled_ != 0; }
  // No function enabled and each as an inactive one leaves it: step()
  // evaluates SSM alone, from the speed.
  [[nodiscard]] bool at_rest() const { return enabled_ == 0 && idle_; }

  // A violation tripped this function (latched until clear_trip()).
  [[nodiscard]] bool tripped(int fn) const { return ((trip_ >> fn) & 1u) != 0; }
  // tripped() of every function at once, bit fn for function fn.
  [[nodiscard]] std::uint8_t trips() const { return trip_; }
  // The violation that tripped `fn` is still present (SLS/SSR: speed still
  // outside the limit in force at the trip; SDI/SOS: a one-time event).
  [[nodiscard]] bool cause_present(int fn, double speed_rpm) const;
  void clear_trip(int fn) { trip_ = static_cast<std::uint8_t>(trip_ & ~(1u << fn)); }

  // Status bits of spec §2.4 (F-data Out).
  [[nodiscard]] bool ok(int fn) const { return status_[fn]; }
  [[nodiscard]] bool ssm() const { return status_[kCount]; }
  // ok() of every function and ssm() in one word (a key: equal words,
  // equal status bits): ok(fn) in byte fn, ssm() in byte kCount.
  [[nodiscard]] std::uint64_t status_key() const {
    std::uint64_t k;
    std::memcpy(&k, status_.data(), sizeof k);  // bytes 6 and 7 are always 0
    return k;
  }
  [[nodiscard]] bool monitoring(int fn) const { return st_[fn].monitoring; }

  void reset();

 private:
  struct State {
    bool requested = false;
    bool monitoring = false;
    TIME since{};
    TIME integ{};
    double ref_pos = 0.0;
    double last_pos = 0.0;
    double wrong_way = 0.0;
  };

  void step_functions(TIME now, TIME dt, const Request& rq, double speed_rpm, double position_inc);

  const NordIParams& ip_;
  std::array<State, kCount> st_{};
  std::uint8_t trip_ = 0;  // bit fn: fn tripped (one word: the device reads all five per step)
  std::uint8_t trip_level_ = 0;
  // ok(fn) in byte fn, ssm() in byte kCount, bytes 6 and 7 always 0:
  // status_key() loads the eight as one word.
  alignas(8) std::array<bool, 8> status_{};
  static_assert(kCount + 1 <= 6);
  // Bit fn: P820 enables function fn (the i-parameters are fixed for the
  // device's life, so once at construction).
  std::uint8_t enabled_ = 0;
  // The SSM limit P823[-07] as a double, once (SSM is evaluated every step).
  double ssm_max_;
  // Every function sits as an inactive one leaves it (not requested, not
  // monitoring, no count, status 0): true after reset() and after a step in
  // which none was active. Such a step again changes nothing but SSM.
  bool idle_ = true;
};

}  // namespace plc::sim

// Noise from a seed for the device models (the PR5510's filling process,
// the plant core's measurement noise): xorshift64* with Box-Muller,
// portable, so the same seed gives the same numbers with any standard
// library (the <random> distributions do not promise that), and a recorded
// trace stays bit for bit what it was. tests/plant pins its first numbers.
#pragma once

#include <cmath>
#include <cstdint>

namespace plc::sim {

class SeededNoise {
 public:
  explicit SeededNoise(std::uint64_t seed) : s_(seed ? seed : 0x9E3779B97F4A7C15ULL) {}
  std::uint64_t next_u64() {
    s_ ^= s_ >> 12;
    s_ ^= s_ << 25;
    s_ ^= s_ >> 27;
    return s_ * 0x2545F4914F6CDD1DULL;
  }
  double uniform() { return static_cast<double>(next_u64() >> 11) * (1.0 / 9007199254740992.0); }
  // 2 * uniform() - 1, with the two scalings in one: uniform() is an
  // integer below 2^53 times 2^-53, exact, and doubling it is exact, so
  // the integer times 2^-52 is the same double (one multiply fewer).
  double uniform_pm1() {
    return static_cast<double>(next_u64() >> 11) * (1.0 / 4503599627370496.0) - 1.0;
  }
  // Standard normal (mean 0, sigma 1), two per pair of uniforms.
  double gaussian() {
    if (has_spare_) return take_spare();
    return gaussian_pair();
  }
  // gaussian() in its two parts, for a caller that takes the spare apart
  // from the draw (the PR5510's ms tick: the draw's libm calls out of line):
  // while has_spare(), gaussian() is take_spare(), else gaussian_pair().
  [[nodiscard]] bool has_spare() const { return has_spare_; }
  double take_spare() {
    has_spare_ = false;
    return spare_;
  }
  double gaussian_pair() {
    // uniform() with its integer at hand: u = k * 2^-53 is below 1e-300
    // only for k = 0 (the next one is 2^-53), so the integer is tested.
    const std::uint64_t k = next_u64() >> 11;
    const double u = k == 0 ? 1e-300 : static_cast<double>(k) * (1.0 / 9007199254740992.0);
    const double v = uniform();
    const double r = std::sqrt(-2.0 * std::log(u));
    spare_ = r * std::sin(6.283185307179586 * v);
    has_spare_ = true;
    return r * std::cos(6.283185307179586 * v);
  }

 private:
  std::uint64_t s_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace plc::sim

// The dead-time buffer of a plant: per input, the last d+2 samples, so that
// a sample can take u[k-d] and u[k-d-1] (zoh_discretisation.hpp). Sized
// once at construction; push() neither allocates nor loops over the delay.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace plc::plant {

// Beyond this many samples of dead time a config is refused (8 MB per input
// at one double per sample): a dead time of hours at a millisecond sample is
// a mistake, not a plant.
inline constexpr std::int64_t kMaxDelaySamples = 1'000'000;

class DeadTimeLine {
 public:
  DeadTimeLine() = default;
  // delays[i]: d of input i (0 .. kMaxDelaySamples). `initial` fills the
  // history: the input the plant saw before the first sample.
  DeadTimeLine(std::span<const std::int64_t> delays, std::span<const double> initial);

  // Stores u[k] for every input and gives u[k-d] (now) and u[k-d-1] (before)
  // per input.
  void push(std::span<const double> u, std::span<double> now, std::span<double> before) {
    for (std::size_t i = 0; i < lines_.size(); ++i) {
      Line& l = lines_[i];
      double* b = buf_.data() + l.offset;
      b[l.head] = u[i];
      // With len = d + 2: k-d is head + 2 and k-d-1 is head + 1, modulo len.
      std::uint32_t a = l.head + 2, c = l.head + 1;
      if (a >= l.len) a -= l.len;
      if (c >= l.len) c -= l.len;
      now[i] = b[a];
      before[i] = b[c];
      l.head = l.head + 1 == l.len ? 0 : l.head + 1;
    }
  }

  [[nodiscard]] std::size_t inputs() const { return lines_.size(); }

 private:
  struct Line {
    std::size_t offset = 0;
    std::uint32_t len = 2;  // d + 2
    std::uint32_t head = 0;
  };
  std::vector<Line> lines_;
  std::vector<double> buf_;
};

}  // namespace plc::plant

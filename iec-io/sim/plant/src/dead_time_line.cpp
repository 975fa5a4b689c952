#include "plc/sim/plant/dead_time_line.hpp"

#include <algorithm>
#include <stdexcept>

namespace plc::plant {

DeadTimeLine::DeadTimeLine(std::span<const std::int64_t> delays, std::span<const double> initial) {
  if (initial.size() != delays.size())
    throw std::invalid_argument("DeadTimeLine: one initial value per input");
  std::size_t total = 0;
  for (std::int64_t d : delays) {
    if (d < 0 || d > kMaxDelaySamples)
      throw std::invalid_argument("DeadTimeLine: delay out of range");
    Line l;
    l.offset = total;
    l.len = static_cast<std::uint32_t>(d + 2);
    lines_.push_back(l);
    total += l.len;
  }
  buf_.resize(total);
  for (std::size_t i = 0; i < lines_.size(); ++i)
    std::fill_n(buf_.begin() + static_cast<std::ptrdiff_t>(lines_[i].offset), lines_[i].len,
                initial[i]);
}

}  // namespace plc::plant

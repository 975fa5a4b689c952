#include "plc/io/process_image.hpp"

#include <algorithm>
#include <cstring>

namespace plc::io {

void ProcessImage::resize(const ImageSizes& s) {
  i_.assign(s.inputs, 0);
  q_.assign(s.outputs, 0);
  m_.assign(s.memory, 0);
}

bool ProcessImage::contains(const IecAddress& a) const {
  return std::size_t(a.byte) + a.width_bytes() <= area(a.area).size();
}

void ProcessImage::copy_from(const ProcessImage& o) {
  // std::copy, not memcpy: an area may be empty (image: {memory: 0}), and
  // an empty vector's data() may be null, which memcpy must never get.
  std::copy(o.i_.begin(), o.i_.end(), i_.begin());
  std::copy(o.q_.begin(), o.q_.end(), q_.begin());
  std::copy(o.m_.begin(), o.m_.end(), m_.begin());
}

void merge_changes(std::span<std::uint8_t> dst, std::span<const std::uint8_t> before,
                   std::span<const std::uint8_t> after) {
  const std::size_t n = dst.size();
  std::size_t i = 0;
  // Eight bytes at a time; memcpy keeps it free of alignment assumptions.
  for (; i + 8 <= n; i += 8) {
    std::uint64_t d, b, a;
    std::memcpy(&d, dst.data() + i, 8);
    std::memcpy(&b, before.data() + i, 8);
    std::memcpy(&a, after.data() + i, 8);
    const std::uint64_t changed = a ^ b;
    if (changed) {
      d = (d & ~changed) | (a & changed);
      std::memcpy(dst.data() + i, &d, 8);
    }
  }
  for (; i < n; ++i) {
    const std::uint8_t changed = after[i] ^ before[i];
    dst[i] = static_cast<std::uint8_t>((dst[i] & ~changed) | (after[i] & changed));
  }
}

}  // namespace plc::io

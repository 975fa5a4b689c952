// The process image: %I (inputs), %Q (outputs) and %M (memory) byte areas.
//
// There is one global image and one private copy per task. A task copies the
// global image in at the start of its scan and merges back only the bits it
// changed at the end (see merge_changes), so tasks with different periods can
// share %Q and %M bytes without overwriting each other's bits.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "plc/io/byte_order.hpp"
#include "plc/io/iec_address.hpp"

namespace plc::io {

struct ImageSizes {
  std::size_t inputs = 1024, outputs = 1024, memory = 4096;
};

class ProcessImage {
 public:
  ProcessImage() = default;
  explicit ProcessImage(const ImageSizes& s) { resize(s); }
  void resize(const ImageSizes& s);

  std::span<std::uint8_t> area(Area a) {
    return a == Area::Input    ? std::span<std::uint8_t>(i_)
           : a == Area::Output ? std::span<std::uint8_t>(q_)
                               : std::span<std::uint8_t>(m_);
  }
  [[nodiscard]] std::span<const std::uint8_t> area(Area a) const {
    return const_cast<ProcessImage*>(this)->area(a);
  }
  [[nodiscard]] ImageSizes sizes() const { return {i_.size(), q_.size(), m_.size()}; }
  // Whether an address (of its width) lies inside the image.
  [[nodiscard]] bool contains(const IecAddress& a) const;
  std::uint8_t* at(const IecAddress& a) { return area(a.area).data() + a.byte; }

  void copy_from(const ProcessImage& other);  // same sizes

 private:
  std::vector<std::uint8_t> i_, q_, m_;
};

// dst := dst with every bit that differs between `before` and `after` taken
// from `after`. Bits the task did not change keep what other tasks wrote.
void merge_changes(std::span<std::uint8_t> dst, std::span<const std::uint8_t> before,
                   std::span<const std::uint8_t> after);

}  // namespace plc::io

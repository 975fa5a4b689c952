// The far end of the wire for the FB-side targets: a device model whose
// cyclic input bytes and record answers come from the fuzz input, hosted in
// a SimDevice that the FB's port is bound to, so the FB decodes whatever a
// faulty or hostile device could send.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "fuzz_input.hpp"
#include "plc/io/device_model.hpp"
#include "plc/io/sim_device.hpp"

namespace plc::fuzz {

class FuzzDevice final : public io::DeviceModel {
 public:
  FuzzDevice(FuzzInput& in, std::size_t in_size, std::size_t out_size)
      : in_(in), in_size_(in_size), out_size_(out_size) {}

  [[nodiscard]] std::size_t input_size() const override { return in_size_; }
  [[nodiscard]] std::size_t output_size() const override { return out_size_; }
  void step(TIME, TIME, std::span<const std::uint8_t>, std::span<std::uint8_t> to_plc) override {
    // One control byte per step: bit 0 new inputs (or keep the last ones,
    // as a device refreshing slower than the scan), bits 1-5 all clear: the
    // device falls silent from the next step on.
    const std::uint8_t c = in_.byte();
    if (c & 1) in_.fill(to_plc);
    set_answering_now((c & 0x3E) != 0 || in_.empty());
  }
  // Any record error code (also ones no device should send), or data of any
  // length up to what the request allows.
  io::RecordError read_record(std::uint16_t, std::span<std::uint8_t> out,
                              std::size_t& length) override {
    const std::uint8_t e = in_.byte();
    if (e & 0x80) return static_cast<io::RecordError>(e & 0x7F);
    const auto d = in_.bytes(std::size_t{in_.byte()} % (out.size() + 1));
    for (std::size_t i = 0; i < d.size(); ++i) out[i] = d[i];
    length = d.size();
    return io::RecordError::None;
  }
  io::RecordError write_record(std::uint16_t, std::span<const std::uint8_t>) override {
    const std::uint8_t e = in_.byte();
    return (e & 0x80) ? static_cast<io::RecordError>(e & 0x7F) : io::RecordError::None;
  }

 private:
  FuzzInput& in_;
  std::size_t in_size_, out_size_;
};

// A SimDevice hosting a FuzzDevice.
inline std::unique_ptr<io::SimDevice> fuzz_device(FuzzInput& in, std::size_t in_size,
                                                  std::size_t out_size) {
  return std::make_unique<io::SimDevice>(std::make_unique<FuzzDevice>(in, in_size, out_size));
}

}  // namespace plc::fuzz

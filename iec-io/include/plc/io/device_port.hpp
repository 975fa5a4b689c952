// An FB's handle on one device: its cyclic input and output bytes in the
// task's process image, its communication state, and its acyclic channel.
//
// An FB declares a DevicePort member and lists it in PLC_REFLECT; the runtime
// binds it by device name (from the code, or overridden by the cell config's
// `bind:`) when the program is set up. Tests bind it to a SimDevice directly.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "plc/fixed_string.hpp"
#include "plc/io/device_link.hpp"

namespace plc::io {

class DevicePort {
 public:
  DevicePort() = default;
  explicit DevicePort(std::string_view device) : device_(device) {}

  [[nodiscard]] std::string_view device_name() const { return device_.view(); }
  void set_device_name(std::string_view n) { device_ = n; }

  // Bytes the device sent (the image's %I part of this device) and bytes the
  // PLC sends (its %Q part). Empty until bound.
  [[nodiscard]] std::span<const std::uint8_t> in() const { return in_; }
  [[nodiscard]] std::span<std::uint8_t> out() const { return out_; }
  [[nodiscard]] bool bound() const { return link_ != nullptr; }

  [[nodiscard]] DeviceState state() const { return link_ ? link_->state() : DeviceState::Offline; }
  [[nodiscard]] bool online() const { return state() == DeviceState::Online; }
  // The device's last alarm (count 0: none; DeviceLink::last_alarm).
  [[nodiscard]] DeviceAlarm last_alarm() const {
    return link_ ? link_->last_alarm() : DeviceAlarm{};
  }

  // Queue an acyclic request; poll r.status() in later scans.
  bool submit(RecordRequest& r) {
    if (!link_) {
      r.set_delivery(false, -1);  // refused at once
      r.fail(RecordError::NotReachable);
      return false;
    }
    return link_->submit(r);
  }

  void bind(std::span<const std::uint8_t> in, std::span<std::uint8_t> out, DeviceLink* link) {
    in_ = in;
    out_ = out;
    link_ = link;
  }

 private:
  FixedString<63> device_;
  std::span<const std::uint8_t> in_;
  std::span<std::uint8_t> out_;
  DeviceLink* link_ = nullptr;
};

}  // namespace plc::io

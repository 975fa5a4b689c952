#include "plc/fb/weighing/string_value.hpp"

namespace plc::weighing {

namespace {
// Common start checks of an Execute edge; returns an ErrorID or kNone.
std::uint16_t start_checks(PR5510_Device* dev, int& slot, std::uint8_t base, bool write) {
  if (dev == nullptr) return error_id::kNoDevice;
  if (slot == PR5510_Device::kNoSlot) slot = dev->attach();
  if (slot == PR5510_Device::kNoSlot) return error_id::kTooManyClients;
  for (std::uint8_t k = 0; k < kStringChunks; ++k) {
    const auto c = static_cast<std::uint8_t>(base + k);
    if (base + k > 0xFF || (write ? !is_defined_write_code(c) : !is_defined_read_code(c)))
      return error_id::kInvalidCode;
  }
  if (!dev->Online) return error_id::kDeviceOffline;
  return error_id::kNone;
}
}  // namespace

void PR5510_ReadString::operator()(const ScanContext&) {
  const bool rising = Execute && !prev_execute_;
  prev_execute_ = Execute;
  if ((Done || Error) && !Execute) {
    Done = Error = false;
    ErrorID = error_id::kNone;
  }
  if (rising && !Busy) {
    Done = Error = false;
    ErrorID = start_checks(Device, slot_, BaseCode, false);
    Error = ErrorID != error_id::kNone;
    Busy = !Error;
    chunk_ = 0;
  }
  if (!Busy) return;
  // Busy may have been set from outside (debugger, HMI) with no job: no
  // device, or every chunk read already; never index past the buffer.
  std::uint16_t err = Device == nullptr         ? error_id::kNoDevice
                      : chunk_ >= kStringChunks ? error_id::kNoJob
                      : Device->Online          ? Device->read_error(slot_)
                                                : error_id::kDeviceOffline;
  if (err == error_id::kNone) {
    const auto code = static_cast<std::uint8_t>(BaseCode + chunk_);
    if (Device->read_valid(slot_, code)) {
      put_string_chunk(reinterpret_cast<char*>(buf_.data()), chunk_, Device->read_raw());
      if (++chunk_ == kStringChunks) {
        Text = trim_string(reinterpret_cast<const char*>(buf_.data()));
        Busy = false;
        Done = true;
        return;
      }
    }
    Device->request_read(slot_, static_cast<std::uint8_t>(BaseCode + chunk_));
    return;
  }
  Busy = false;
  Error = true;
  ErrorID = err;
}

void PR5510_WriteString::operator()(const ScanContext&) {
  const bool rising = Execute && !prev_execute_;
  prev_execute_ = Execute;
  if ((Done || Error) && !Execute) {
    Done = Error = false;
    ErrorID = error_id::kNone;
  }
  if (rising && !Busy) {
    Done = Error = false;
    ErrorID = start_checks(Device, slot_, BaseCode, true);
    Error = ErrorID != error_id::kNone;
    Busy = !Error;
    chunk_ = 0;
    latched_ = Text;
    if (Busy) {
      Device->ack_write(slot_);
      Device->request_write(slot_, BaseCode, string_chunk(latched_.view(), 0));
    }
  }
  if (!Busy) return;
  if (Device == nullptr || chunk_ >= kStringChunks) {  // Busy set from outside, no job
    Busy = false;
    Error = true;
    ErrorID = Device == nullptr ? error_id::kNoDevice : error_id::kNoJob;
    return;
  }
  switch (Device->write_status(slot_)) {
    case WriteStatus::Done:
      Device->ack_write(slot_);
      if (++chunk_ == kStringChunks) {
        Busy = false;
        Done = true;
      } else {
        Device->request_write(slot_, static_cast<std::uint8_t>(BaseCode + chunk_),
                              string_chunk(latched_.view(), chunk_));
      }
      break;
    case WriteStatus::Error:
      Device->ack_write(slot_);
      Busy = false;
      Error = true;
      ErrorID = Device->write_error(slot_);
      break;
    default:
      break;
  }
}

}  // namespace plc::weighing

#include "plc/profinet/device/record_status.hpp"

namespace plc::profinet {

namespace {
constexpr std::uint8_t kAppReadError = 0xA0;
constexpr std::uint8_t kAppWriteError = 0xA1;
constexpr std::uint8_t kAppBusy = 0xA7;
constexpr std::uint8_t kInvalidIndex = 0xB0;
constexpr std::uint8_t kWriteLength = 0xB1;
constexpr std::uint8_t kInvalidSlot = 0xB2;
constexpr std::uint8_t kStateConflict = 0xB5;
constexpr std::uint8_t kResourceBusy = 0xC2;
}  // namespace

PnioStatus record_status(io::RecordError e, bool write) {
  const std::uint8_t code = write ? pnio_error::kCodeWrite : pnio_error::kCodeRead;
  const auto v = static_cast<std::uint16_t>(e);
  if (v == 0) return {};
  if (v >= 0x100)
    return {code, pnio_error::kDecodeManufacturer, static_cast<std::uint8_t>(v >> 8),
            static_cast<std::uint8_t>(v)};
  switch (e) {
    case io::RecordError::InvalidIndex:
      return {code, pnio_error::kDecodePnioRw, kInvalidIndex, 0};
    case io::RecordError::InvalidLength:
      return {code, pnio_error::kDecodePnioRw, kWriteLength, 0};
    case io::RecordError::InvalidState:
      return {code, pnio_error::kDecodePnioRw, kStateConflict, 0};
    case io::RecordError::DeviceBusy:
      return {code, pnio_error::kDecodePnioRw, kResourceBusy, 0};
    default:
      return {code, pnio_error::kDecodePnioRw, write ? kAppWriteError : kAppReadError,
              static_cast<std::uint8_t>(v)};
  }
}

PnioStatus invalid_slot_status(bool write) {
  return {write ? pnio_error::kCodeWrite : pnio_error::kCodeRead, pnio_error::kDecodePnioRw,
          kInvalidSlot, 0};
}

io::RecordError record_error_from(const PnioStatus& s) {
  if (s.ok()) return io::RecordError::None;
  if (s.error_decode == pnio_error::kDecodeManufacturer)
    return static_cast<io::RecordError>((std::uint16_t{s.error_code1} << 8) | s.error_code2);
  if (s.error_decode == pnio_error::kDecodePnioRw) {
    switch (s.error_code1) {
      case kInvalidIndex:
      case kInvalidSlot:
        return io::RecordError::InvalidIndex;
      case kWriteLength:
        return io::RecordError::InvalidLength;
      case kStateConflict:
        return io::RecordError::InvalidState;
      case kResourceBusy:
      case kAppBusy:
        return io::RecordError::DeviceBusy;
      case kAppReadError:
      case kAppWriteError:
        if (s.error_code2 != 0) return static_cast<io::RecordError>(s.error_code2);
        break;
      default:
        break;
    }
  }
  return io::RecordError::InvalidState;
}

}  // namespace plc::profinet

#include "plc/fb/acdrive/ac_drive_attribute.hpp"

#include <algorithm>

#include "plc/fb/acdrive/error_ids.hpp"
#include "plc/fb/acdrive/profile_objects.hpp"
#include "plc/io/explicit_message.hpp"

namespace plc::acdrive {

namespace em = io::explicit_msg;

void AcDriveAttribute::finish_error(std::uint16_t e) {
  Error = true;
  Busy = false;
  ErrorID = e;
}

void AcDriveAttribute::start(const ScanContext& ctx, AcDrive& drive) {
  if (rec_.busy()) return finish_error(error_id::kBusy);  // a timed-out request still queued
  if (!drive.Port.bound() || !drive.Port.online()) return finish_error(error_id::kOffline);
  const ProfileAttr* known = resolve_attr(Class, Instance, Attribute);
  signed_ = known && is_signed(known->type);
  std::array<std::uint8_t, 4> data{};
  std::size_t n = 0;
  if (Service == em::kSetAttributeSingle) {
    n = Length != 0 ? Length : (known ? size_of(known->type) : 0);
    if (n != 1 && n != 2) return finish_error(error_id::kBadInput);
    const bool fits =
        known && is_signed(known->type)
            ? (n == 1 ? Value >= -128 && Value <= 127 : Value >= -32768 && Value <= 32767)
            : (n == 1 ? Value >= 0 && Value <= 255 : Value >= 0 && Value <= 65535);
    if (!fits) return finish_error(error_id::kBadInput);  // never wrapped
    data[0] = static_cast<std::uint8_t>(Value & 0xFF);
    data[1] = static_cast<std::uint8_t>((Value >> 8) & 0xFF);
  } else if (Service > 0x7F) {
    return finish_error(error_id::kBadInput);
  }
  std::array<std::uint8_t, 8> req{};
  const std::size_t len =
      em::encode_request(Service, {Class, Instance, Attribute}, {data.data(), n}, req);
  rec_.reset();
  if (len == 0 || !rec_.prepare_read(em::record_index(Service), {req.data(), len}))
    return finish_error(error_id::kBadInput);
  t0_ = ctx.now;
  Busy = true;
  drive.Port.submit(rec_);  // a refusal shows as an Error status at once
}

void AcDriveAttribute::operator()(const ScanContext& ctx, AcDrive& drive) {
  const bool edge = Execute && !prev_execute_;
  prev_execute_ = Execute;
  if (!Execute && !Busy) {
    Done = Error = false;
    ErrorID = error_id::kNone;
  }
  if (edge && !Busy) {
    Done = Error = false;
    ErrorID = error_id::kNone;
    GeneralStatus = AdditionalCode = 0;
    start(ctx, drive);
  }
  if (!Busy) return;
  switch (rec_.status()) {
    case io::RecordStatus::Queued:
      if (ctx.now - t0_ > Timeout) finish_error(error_id::kTimeout);
      return;
    case io::RecordStatus::Done: {
      const auto d = rec_.data();
      DataLength = static_cast<USINT>(std::min(d.size(), kMaxData));
      std::copy_n(d.begin(), DataLength, Data.begin());
      std::uint32_t v = 0;
      for (std::size_t i = 0; i < d.size() && i < 4; ++i) v |= std::uint32_t{d[i]} << (8 * i);
      if (signed_ && d.size() == 1) v = static_cast<std::uint32_t>(static_cast<std::int8_t>(v));
      if (signed_ && d.size() == 2) v = static_cast<std::uint32_t>(static_cast<std::int16_t>(v));
      ValueRead = static_cast<DINT>(v);
      Done = true;
      Busy = false;
      rec_.reset();
      return;
    }
    case io::RecordStatus::Error: {
      const std::uint16_t code = rec_.error_code();
      if (code >= 0x100) {
        GeneralStatus = em::general_status(code);
        AdditionalCode = em::additional_code(code);
        finish_error(static_cast<std::uint16_t>(error_id::kErrorResponse | GeneralStatus));
      } else {
        finish_error(static_cast<std::uint16_t>(error_id::kRecordRefused | code));
      }
      rec_.reset();
      return;
    }
    case io::RecordStatus::Idle:
      finish_error(error_id::kBadInput);
      return;
  }
}

}  // namespace plc::acdrive

#include "plc/fb/drive/param_client.hpp"

#include <array>

namespace plc::drive {

ParamRequest make_read(std::uint16_t pnu, std::uint16_t subindex, std::uint8_t elements) {
  ParamRequest r;
  r.request_id = static_cast<std::uint8_t>(RequestId::Read);
  r.pnu = pnu;
  r.subindex = subindex;
  r.num_elements = elements;
  return r;
}

ParamRequest make_write(std::uint16_t pnu, std::uint8_t format, double value,
                        std::uint16_t subindex) {
  ParamRequest r;
  r.request_id = static_cast<std::uint8_t>(RequestId::Write);
  r.pnu = pnu;
  r.subindex = subindex;
  r.format = format;
  r.num_values = 1;
  r.values[0] = double_to_raw(value, format);
  return r;
}

bool ParamClient::start(io::DevicePort& port, std::uint16_t record_index, const ParamRequest& r,
                        TIME now, TIME timeout) {
  if (busy()) {
    fail(kErrParamInput);
    return false;
  }
  req_ = r;
  req_.reference = next_ref_;
  next_ref_ = static_cast<std::uint8_t>(next_ref_ == 255 ? 1 : next_ref_ + 1);
  index_ = record_index;
  t0_ = now;
  timeout_ = timeout;
  error_ = 0;
  std::array<std::uint8_t, io::kRecordMaxBytes> buf{};
  const std::size_t n = req_.encode(buf);
  if (n == 0) {
    fail(kErrParamInput);
    return false;
  }
  rec_.reset();
  rec_.prepare_write(index_, {buf.data(), n});
  state_ = State::Writing;
  if (!port.submit(rec_)) {
    fail(static_cast<std::uint16_t>(kErrParamRecord + rec_.error_code()));
    return false;
  }
  return true;
}

void ParamClient::poll(io::DevicePort& port, TIME now) {
  if (!busy()) return;
  const io::RecordStatus st = rec_.status();
  if (st == io::RecordStatus::Queued) {
    if (now - t0_ > timeout_) fail(kErrParamTimeout);
    return;
  }
  if (state_ == State::Writing) {
    if (st == io::RecordStatus::Error) {
      fail(static_cast<std::uint16_t>(kErrParamRecord + (rec_.error_code() & 0xFF)));
      return;
    }
    rec_.reset();
    rec_.prepare_read(index_);
    state_ = State::Reading;
    if (!port.submit(rec_)) fail(static_cast<std::uint16_t>(kErrParamRecord + rec_.error_code()));
    return;
  }
  // Reading.
  if (st == io::RecordStatus::Error) {
    const auto e = rec_.error();
    if ((e == io::RecordError::InvalidState || e == io::RecordError::DeviceBusy) &&
        now - t0_ <= timeout_) {
      rec_.reset();
      rec_.prepare_read(index_);
      if (!port.submit(rec_)) fail(static_cast<std::uint16_t>(kErrParamRecord + rec_.error_code()));
      return;
    }
    fail(now - t0_ > timeout_
             ? kErrParamTimeout
             : static_cast<std::uint16_t>(kErrParamRecord + (rec_.error_code() & 0xFF)));
    return;
  }
  check_response();
}

void ParamClient::check_response() {
  if (!decode_response(rec_.data(), resp_)) return fail(kErrParamMalformed);
  if (resp_.reference != req_.reference) return fail(kErrParamRefMismatch);
  const std::uint8_t id = resp_.response_id;
  if (id == kResponseErrorFlag) {  // unknown request ID (error 0x21)
    return fail(static_cast<std::uint16_t>(kErrParamResponse + (resp_.error_no & 0xFF)));
  }
  if ((id & 0x7F) != req_.request_id) return fail(kErrParamIdMismatch);
  if (resp_.negative())
    return fail(static_cast<std::uint16_t>(kErrParamResponse + (resp_.error_no & 0xFF)));
  if (req_.request_id == static_cast<std::uint8_t>(RequestId::Read)) {
    const std::size_t want = req_.num_elements == 0 ? 1 : req_.num_elements;
    if (resp_.num_values != want) return fail(kErrParamCount);
  }
  state_ = State::Done;
}

}  // namespace plc::drive

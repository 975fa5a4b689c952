#include "plc/fb/drive/sina_para.hpp"

#include <algorithm>

namespace plc::drive {

void SinaPara::operator()(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  const bool edge = Start && !prev_start_;
  prev_start_ = Start;
  auto finish_error = [&](std::uint16_t e) {
    Error = true;
    ErrorID = e;
    ErrorText = diag_text(e);
    Busy = false;
  };
  if (!Start && !Busy) {
    Done = Error = false;
    ErrorID = 0;
    ErrorText = "";
  }
  if (edge && !Busy) {
    Done = Error = false;
    ErrorID = 0;
    ErrorText = "";
    const std::size_t n = Count == 0 ? 1 : Count;
    if (ReadWrite) Values[0] = Value;
    if (Count > kMaxValues || (ReadWrite && !is_value_format(Format))) {
      finish_error(kErrParamInput);
    } else if (ReadWrite && !std::all_of(Values.begin(), Values.begin() + n,
                                         [&](LREAL v) { return value_fits_format(v, Format); })) {
      finish_error(kErrParamValue);  // Table 4.3.5.1: never wrapped into the format
    } else if (axis.CommError) {
      finish_error(axis.CommError);
    } else {
      ParamRequest r;
      r.request_id = static_cast<std::uint8_t>(ReadWrite ? RequestId::Write : RequestId::Read);
      r.do_id = DoId;
      r.pnu = Pnu;
      r.subindex = Subindex;
      r.num_elements = static_cast<std::uint8_t>(Count);
      if (ReadWrite) {
        r.format = Format;
        r.num_values = static_cast<std::uint8_t>(n);
        for (std::size_t i = 0; i < n; ++i) r.values[i] = double_to_raw(Values[i], Format);
      }
      Busy = true;
      if (!client_.start(axis.Port, RecordIndex, r, ctx.now, Timeout))
        finish_error(client_.error());
    }
  }
  if (Busy) {
    client_.poll(axis.Port, ctx.now);
    if (client_.state() == ParamClient::State::Done) {
      const ParamResponse& resp = client_.response();
      RespFormat = resp.format;
      RespCount = resp.num_values;
      if (!ReadWrite) {
        for (std::size_t i = 0; i < resp.num_values && i < kMaxValues; ++i)
          ValuesRead[i] = raw_to_double(resp.values[i], resp.format);
        ValueRead = ValuesRead[0];
      }
      Done = true;
      Busy = false;
    } else if (client_.state() == ParamClient::State::Error) {
      finish_error(client_.error());
    }
  }
  Ready = !Busy;
  axis.block_done();
}

}  // namespace plc::drive

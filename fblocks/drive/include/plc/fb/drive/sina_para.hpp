// SinaPara: read or write one parameter, or elements of an array parameter,
// through the PROFIdrive parameter channel (spec §6.4), in the style of
// Siemens SINA_PARA_S. Carried by record write/read on RecordIndex (default
// 47 = 0x002F, the base-mode parameter access record SINA_PARA uses; see
// parameter_channel.hpp for why).
//
// Inputs: Start (rising edge), ReadWrite (FALSE read, TRUE write), Pnu
// (use pt_pnu(0x317) / ut_pnu(0x095) or parse_pnu("Pt317")), Subindex, Count
// (0 = one simple value, sent with "number of elements" 0 as the E1 manual
// does; n >= 1 = n array elements from Subindex), Format (write: code of
// Table 4.3.5.1, e.g. 16#06 Uint16, 16#04 Int32, 16#08 Float32), Values
// (write: the values; Value = Values[0]), DoId (0 on the E1), Timeout.
// Outputs: Ready (idle), Busy, Done, Error, ErrorID, ErrorText (for 16#81xx
// the §6.5 name of the drive's error number), RespFormat, RespCount,
// ValueRead (= ValuesRead[0]), ValuesRead.
// ErrorID: 16#81xx negative response with error number xx (every number of
// §6.5), 16#8200-16#8205 response matching and input errors, 16#83xx record
// refused (plc::io::RecordError), 16#8206 a write value that does not fit
// Format (outside the type's range of Table 4.3.5.1, NaN or infinite; not
// sent, never wrapped), 16#8001/8002/8003 the axis' communication error (the
// request is not sent while the axis reports one).
#pragma once

#include <array>
#include <string>

#include "plc/fb/drive/drive_axis.hpp"
#include "plc/fb/drive/param_client.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::drive {

struct SinaPara {
  static constexpr std::size_t kMaxValues = 64;  // PNU 945/947 are Array[64]
  BOOL Start{};
  BOOL ReadWrite{};
  UINT Pnu{};
  UINT Subindex{};
  UINT Count{};
  USINT Format = 0x06;
  LREAL Value{};
  std::array<LREAL, kMaxValues> Values{};
  USINT DoId{};
  UINT RecordIndex = kParamRecordIndex;
  TIME Timeout = std::chrono::seconds(1);
  BOOL Ready = true;
  BOOL Busy{};
  BOOL Done{};
  BOOL Error{};
  WORD ErrorID{};
  STRING ErrorText;
  USINT RespFormat{};
  UINT RespCount{};
  LREAL ValueRead{};
  std::array<LREAL, kMaxValues> ValuesRead{};

  void operator()(const ScanContext& ctx, DriveAxis& axis);
  PLC_REFLECT(Start, ReadWrite, Pnu, Subindex, Count, Format, Value, Values, DoId, RecordIndex,
              Timeout, Ready, Busy, Done, Error, ErrorID, ErrorText, RespFormat, RespCount,
              ValueRead, ValuesRead,
              /* internal state */ client_, prev_start_)
  PLC_INTERNAL(client_, prev_start_)
  // Count is a length (of Values, ValuesRead): a debugger write beyond
  // kMaxValues is refused at once; a program's is refused at the Start edge
  // (ErrorID kErrParamInput).
  PLC_WRITE_CHECK(Count, check_count)
  [[nodiscard]] std::string check_count(UINT n) const {
    return n <= kMaxValues ? "" : "Count must be 0 .. " + std::to_string(kMaxValues);
  }

  ParamClient client_;
  bool prev_start_ = false;
};

}  // namespace plc::drive

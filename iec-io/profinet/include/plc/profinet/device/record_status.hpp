// How a record read/write refused by the hosted model travels as a PNIO
// status, and back: the controller turns it into the RecordError the FB
// sees, so RDREC/WRREC report the same code over PROFINET as over the sim
// plugin (e.g. the NORD F-parameter codes 5711..5726).
//
//   RecordError         PNIOStatus (ErrorCode 0xDE read / 0xDF write)
//   InvalidIndex        xx 80 B0 00  (PNIORW: access, invalid index)
//   InvalidLength       xx 80 B1 00  (access, write length error)
//   InvalidState        xx 80 B5 00  (access, state conflict)
//   DeviceBusy          xx 80 C2 00  (resource, busy)
//   other codes < 256   xx 80 A0/A1 code (application read/write error)
//   model codes >= 256  xx 82 hi lo  (manufacturer specific: the code itself)
// A slot/subslot the device does not have: xx 80 B2 00 (back: InvalidIndex).
#pragma once

#include "plc/io/record_request.hpp"
#include "plc/profinet/wire/rpc.hpp"

namespace plc::profinet {

[[nodiscard]] PnioStatus record_status(io::RecordError e, bool write);
[[nodiscard]] PnioStatus invalid_slot_status(bool write);
// The inverse (None for an OK status).
[[nodiscard]] io::RecordError record_error_from(const PnioStatus& s);

}  // namespace plc::profinet

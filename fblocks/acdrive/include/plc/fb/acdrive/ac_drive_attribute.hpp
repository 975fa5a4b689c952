// AcDriveAttribute: Get_Attribute_Single / Set_Attribute_Single on the
// VF66B's Motor Data (0x28), Control Supervisor (0x29) and AC/DC Drive
// (0x2A) objects and the Parameter object (0x0F, instances 1..19), as an
// explicit message through the asynchronous record path (RDREC-style: the
// request is submitted on the rising edge of Execute and polled in later
// scans). The mapping onto the record path is plc/io/explicit_message.hpp:
// a record read with request bytes class, instance, attribute[, data] at
// index 16#D000 | service.
//
// Inputs: Execute (rising edge), Service (16#0E Get_Attribute_Single, 16#10
// Set_Attribute_Single; any other code is sent as a service on class and
// instance, e.g. 16#05 Reset), Class, Instance, Attribute, Value (Set: the
// value, little-endian on the wire), Length (Set: 0 = the attribute's size
// from the manual's tables, profile_objects.hpp; 1 or 2 for an attribute
// outside them), Timeout.
// Outputs: Done, Busy, Error, ErrorID (error_ids.hpp: 16#85gg Error
// Response with general status gg of §11.1, AdditionalCode beside it;
// 16#83xx record refused; 16#8001 offline; 16#8201 bad input; 16#8202
// previous request still in flight; 16#8203 timeout), GeneralStatus,
// AdditionalCode, ValueRead (Get: the value; signed for INT/SINT
// attributes of the tables, else unsigned), DataLength, Data (raw answer).
// Done/Error hold while Execute stays TRUE, and for one scan when Execute
// fell before the answer came.
// Set of 0x29 attr 12 FaultRst = 1 is a fault reset (0->1, Table 3.4.2).
// Run1/Run2/NetCtrl/NetRef/SpeedRef take a Set too, but the drive holds the
// last write, and the AcDrive's next output message writes them again
// (fblocks/acdrive/README.md, "Explicit Set and I/O: which wins").
#pragma once

#include <array>

#include "plc/fb/acdrive/ac_drive.hpp"
#include "plc/io/record_request.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::acdrive {

struct AcDriveAttribute {
  static constexpr std::size_t kMaxData = 32;
  BOOL Execute{};
  USINT Service = 0x0E;
  USINT Class = 0x2A;
  USINT Instance = 1;
  USINT Attribute = 7;
  DINT Value{};
  USINT Length{};
  TIME Timeout = std::chrono::seconds(1);
  BOOL Done{};
  BOOL Busy{};
  BOOL Error{};
  WORD ErrorID{};
  USINT GeneralStatus{};
  USINT AdditionalCode{};
  DINT ValueRead{};
  USINT DataLength{};
  std::array<USINT, kMaxData> Data{};

  void operator()(const ScanContext& ctx, AcDrive& drive);
  PLC_REFLECT(Execute, Service, Class, Instance, Attribute, Value, Length, Timeout, Done, Busy,
              Error, ErrorID, GeneralStatus, AdditionalCode, ValueRead, DataLength, Data,
              /* internal state */ prev_execute_, t0_, signed_)
  PLC_INTERNAL(prev_execute_, t0_, signed_)

  void start(const ScanContext& ctx, AcDrive& drive);
  void finish_error(std::uint16_t e);
  bool prev_execute_ = false;
  TIME t0_{};
  bool signed_ = false;
  io::RecordRequest rec_;  // the request in flight (not reflected: owned by the record path)
};

}  // namespace plc::acdrive

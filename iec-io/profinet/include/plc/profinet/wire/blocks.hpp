// PROFINET IO blocks carried in the RPC body (IEC 61158-6-10 §5.2 "Coding
// of the fields of the IO blocks"; the Connect/Write/Read/Control PDUs of
// §5.1 "Syntax"). Every block starts with
//   BlockType (2) | BlockLength (2, counts from BlockVersionHigh on) |
//   BlockVersionHigh (1) = 1 | BlockVersionLow (1) = 0
// All fields big-endian, UUIDs included.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "plc/profinet/wire/codec.hpp"
#include "plc/profinet/wire/ethernet.hpp"
#include "plc/profinet/wire/rpc.hpp"

namespace plc::profinet {

namespace block {
inline constexpr std::uint16_t kAlarmNotificationHigh = 0x0001;
inline constexpr std::uint16_t kAlarmNotificationLow = 0x0002;
inline constexpr std::uint16_t kWriteReqHeader = 0x0008;
inline constexpr std::uint16_t kReadReqHeader = 0x0009;
inline constexpr std::uint16_t kArBlockReq = 0x0101;
inline constexpr std::uint16_t kIocrBlockReq = 0x0102;
inline constexpr std::uint16_t kAlarmCrBlockReq = 0x0103;
inline constexpr std::uint16_t kExpectedSubmoduleBlockReq = 0x0104;
inline constexpr std::uint16_t kArRpcBlockReq = 0x0107;
inline constexpr std::uint16_t kPrmEndReq = 0x0110;            // IODControlReq (PrmEnd)
inline constexpr std::uint16_t kApplicationReadyReq = 0x0112;  // IOXControlReq (ApplicationReady)
inline constexpr std::uint16_t kReleaseReq = 0x0114;           // IODReleaseReq
inline constexpr std::uint16_t kAlarmAckHigh = 0x8001;
inline constexpr std::uint16_t kAlarmAckLow = 0x8002;
inline constexpr std::uint16_t kWriteResHeader = 0x8008;
inline constexpr std::uint16_t kReadResHeader = 0x8009;
inline constexpr std::uint16_t kArBlockRes = 0x8101;
inline constexpr std::uint16_t kIocrBlockRes = 0x8102;
inline constexpr std::uint16_t kAlarmCrBlockRes = 0x8103;
inline constexpr std::uint16_t kModuleDiffBlock = 0x8104;
inline constexpr std::uint16_t kArServerBlock = 0x8106;
inline constexpr std::uint16_t kPrmEndRes = 0x8110;
inline constexpr std::uint16_t kApplicationReadyRes = 0x8112;
inline constexpr std::uint16_t kReleaseRes = 0x8114;
inline constexpr std::size_t kHeaderLength = 6;  // type, length, version
}  // namespace block

// A block header as read; `body` is the bytes after the version (length - 2).
struct BlockView {
  std::uint16_t type = 0;
  std::uint16_t length = 0;
  std::uint8_t version_high = 1;
  std::uint8_t version_low = 0;
  std::span<const std::uint8_t> body;
};
// Reads one block header and checks the length against the bytes left.
WireStatus read_block(ByteReader& r, BlockView& out);
// Writes a header with a length placeholder; end_block() fills it in.
std::size_t begin_block(ByteBuilder& b, std::uint16_t type, std::uint8_t version_low = 0);
void end_block(ByteBuilder& b, std::size_t start);

// --- Connect ----------------------------------------------------------------

namespace ar {
inline constexpr std::uint16_t kTypeIocarSingle = 0x0001;
// ARProperties: bit 4 = Supervisor takeover allowed, bits 0..2 State (1 = Active),
// bit 30 = StartupMode advanced, bit 31 = PullModuleAlarmAllowed.
inline constexpr std::uint32_t kPropertiesStateActive = 0x00000001;
inline constexpr std::uint32_t kPropertiesParameterServerCm = 0x00000010;
inline constexpr std::uint32_t kPropertiesDefault =
    kPropertiesStateActive | kPropertiesParameterServerCm;
}  // namespace ar

// ARBlockReq 0x0101.
struct ArBlockReq {
  std::uint16_t ar_type = ar::kTypeIocarSingle;
  Uuid ar_uuid;
  std::uint16_t session_key = 0;
  Mac cm_initiator_mac{};
  Uuid cm_initiator_object_uuid;
  std::uint32_t ar_properties = ar::kPropertiesDefault;
  std::uint16_t activity_timeout_factor = 600;  // x 100 ms
  std::uint16_t initiator_udp_rt_port = kRpcUdpPort;
  std::string station_name;  // the controller's CMInitiatorStationName
};
// ARBlockRes 0x8101.
struct ArBlockRes {
  std::uint16_t ar_type = ar::kTypeIocarSingle;
  Uuid ar_uuid;
  std::uint16_t session_key = 0;
  Mac cm_responder_mac{};
  std::uint16_t responder_udp_rt_port = kRpcUdpPort;
};

namespace iocr {
inline constexpr std::uint16_t kTypeInput = 0x0001;   // device -> controller
inline constexpr std::uint16_t kTypeOutput = 0x0002;  // controller -> device
inline constexpr std::uint16_t kLtProfinet = 0x8892;
inline constexpr std::uint32_t kPropertiesRtClass1 = 0x00000001;  // bits 0..3 RTClass
inline constexpr std::uint16_t kTagHeaderPriority6 = 0xC000;      // VLAN 0, priority 6
inline constexpr std::uint32_t kFrameSendOffsetBestEffort = 0xFFFFFFFF;
inline constexpr std::size_t kMinCSduLength = 40;  // RT_CLASS_1 C_SDU
inline constexpr std::size_t kMaxCSduLength = 1440;
// IOPS/IOCS: bit 7 DataState (1 = GOOD), bits 6..5 Instance, bit 0 Extension.
inline constexpr std::uint8_t kIoxsGood = 0x80;
inline constexpr std::uint8_t kIoxsBad = 0x00;
}  // namespace iocr

// One IO data object or IOCS entry: where its bytes are in the C_SDU.
struct IocrEntry {
  std::uint16_t slot = 0;
  std::uint16_t subslot = 0;
  std::uint16_t frame_offset = 0;
};
struct IocrApi {
  std::uint32_t api = 0;
  std::vector<IocrEntry> data_objects;  // IODataObjectFrameOffset (data then IOPS)
  std::vector<IocrEntry> iocs;          // IOCSFrameOffset
};
// IOCRBlockReq 0x0102.
struct IocrBlockReq {
  std::uint16_t iocr_type = iocr::kTypeInput;
  std::uint16_t iocr_reference = 1;
  std::uint16_t lt = iocr::kLtProfinet;
  std::uint32_t iocr_properties = iocr::kPropertiesRtClass1;
  std::uint16_t data_length = iocr::kMinCSduLength;  // C_SDU length
  std::uint16_t frame_id =
      0;  // input: the controller's choice; output: 0xFFFF lets the device choose
  std::uint16_t send_clock_factor = 32;  // x 31.25 us
  std::uint16_t reduction_ratio = 32;
  std::uint16_t phase = 1;
  std::uint16_t sequence = 0;
  std::uint32_t frame_send_offset = iocr::kFrameSendOffsetBestEffort;
  std::uint16_t watchdog_factor = 3;
  std::uint16_t data_hold_factor = 3;
  std::uint16_t iocr_tag_header = iocr::kTagHeaderPriority6;
  Mac multicast_mac{};
  std::vector<IocrApi> apis;
};
// IOCRBlockRes 0x8102.
struct IocrBlockRes {
  std::uint16_t iocr_type = iocr::kTypeInput;
  std::uint16_t iocr_reference = 1;
  std::uint16_t frame_id = 0;
};

namespace alarm_cr {
inline constexpr std::uint16_t kType = 0x0001;
inline constexpr std::uint16_t kDefaultMaxData = 200;
inline constexpr std::uint16_t kTagHeaderHigh = 0xC000;  // priority 6
inline constexpr std::uint16_t kTagHeaderLow = 0xA000;   // priority 5
}  // namespace alarm_cr
// AlarmCRBlockReq 0x0103.
struct AlarmCrBlockReq {
  std::uint16_t alarm_cr_type = alarm_cr::kType;
  std::uint16_t lt = iocr::kLtProfinet;
  std::uint32_t properties = 0;          // bit 0 priority (0: use both), bit 1 transport UDP
  std::uint16_t rta_timeout_factor = 1;  // x 100 ms
  std::uint16_t rta_retries = 3;
  std::uint16_t local_alarm_reference = 1;
  std::uint16_t max_alarm_data_length = alarm_cr::kDefaultMaxData;
  std::uint16_t tag_header_high = alarm_cr::kTagHeaderHigh;
  std::uint16_t tag_header_low = alarm_cr::kTagHeaderLow;
};
// AlarmCRBlockRes 0x8103.
struct AlarmCrBlockRes {
  std::uint16_t alarm_cr_type = alarm_cr::kType;
  std::uint16_t local_alarm_reference = 1;  // the device's
  std::uint16_t max_alarm_data_length = alarm_cr::kDefaultMaxData;
};

namespace submodule {
// SubmoduleProperties bits 0..1: Type.
inline constexpr std::uint16_t kTypeNoIo = 0;
inline constexpr std::uint16_t kTypeInput = 1;
inline constexpr std::uint16_t kTypeOutput = 2;
inline constexpr std::uint16_t kTypeInputOutput = 3;
// SubmoduleProperties bits 2..5.
inline constexpr std::uint16_t kSharedInput = 0x0004;
inline constexpr std::uint16_t kReduceInputLength = 0x0008;
inline constexpr std::uint16_t kReduceOutputLength = 0x0010;
inline constexpr std::uint16_t kDiscardIoxs = 0x0020;
// DataDescription
inline constexpr std::uint16_t kDataInput = 1;
inline constexpr std::uint16_t kDataOutput = 2;
}  // namespace submodule

// One DataDescription of an expected submodule, as it is on the wire.
struct DataDescription {
  std::uint16_t direction = submodule::kDataInput;
  std::uint16_t length = 0;  // SubmoduleDataLength
  std::uint8_t length_iocs = 1;
  std::uint8_t length_iops = 1;
};

// One expected submodule: ident, and its IO data lengths (without IOPS).
// What a controller builds: the type and DataDescriptions follow from the
// lengths (none -> NO_IO with one input description of length 0, input,
// output or both). What a device decodes also keeps the Type and the
// DataDescriptions exactly as received, because a device checks those one
// by one (p-net's pf_cmdev.c: ExpectedSubmoduleBlockReq codes 12..16);
// the encoder writes them as they are when present.
struct ExpectedSubmodule {
  std::uint16_t subslot = 0;
  std::uint32_t submodule_ident = 0;
  std::uint16_t properties = 0;  // bits 2.. (shared input, reduce lengths...); type is apart
  std::uint16_t input_length = 0;
  std::uint16_t output_length = 0;
  std::uint8_t length_iocs = 1;
  std::uint8_t length_iops = 1;
  std::optional<std::uint16_t> wire_type{};     // SubmoduleProperties.Type as received
  std::vector<DataDescription> descriptions{};  // as received (empty: derived from the lengths)
  // wire_type when present, else derived from the lengths.
  [[nodiscard]] std::uint16_t type() const;
  // In the input CR (NO_IO counts as input) / in the output CR.
  [[nodiscard]] bool has_input() const { return type() != submodule::kTypeOutput; }
  [[nodiscard]] bool has_output() const {
    return type() == submodule::kTypeOutput || type() == submodule::kTypeInputOutput;
  }
  // The DataDescriptions as they go on the wire: `descriptions` when
  // present, else the ones the lengths give.
  [[nodiscard]] std::vector<DataDescription> wire_descriptions() const;
  // The first description of that direction (p-net's lookup), or nullptr.
  [[nodiscard]] const DataDescription* description(std::uint16_t direction) const;
};
struct ExpectedModule {
  std::uint32_t api = 0;
  std::uint16_t slot = 0;
  std::uint32_t module_ident = 0;
  std::uint16_t module_properties = 0;
  std::vector<ExpectedSubmodule> submodules;
};
// ExpectedSubmoduleBlockReq 0x0104 (one block may carry several APIs/slots;
// we send one block per module).
struct ExpectedSubmoduleBlockReq {
  std::vector<ExpectedModule> modules;
};

namespace module_state {
inline constexpr std::uint16_t kNoModule = 0;
inline constexpr std::uint16_t kWrongModule = 1;
inline constexpr std::uint16_t kProperModule = 2;
inline constexpr std::uint16_t kSubstitute = 3;
}  // namespace module_state
namespace submodule_state {
// SubmoduleState with FormatIndicator = 1 (bit 15); bits 11..14 IdentInfo
// (0 OK, 1 substitute, 2 wrong, 3 no submodule), bits 7..10 ARInfo (0 own).
inline constexpr std::uint16_t kOk = 0x8000;
inline constexpr std::uint16_t kSubstitute = 0x8800;
inline constexpr std::uint16_t kWrong = 0x9000;
inline constexpr std::uint16_t kNoSubmodule = 0x9800;
}  // namespace submodule_state
struct ModuleDiffSubmodule {
  std::uint16_t subslot = 0;
  std::uint32_t submodule_ident = 0;
  std::uint16_t state = submodule_state::kOk;
};
struct ModuleDiffModule {
  std::uint16_t slot = 0;
  std::uint32_t module_ident = 0;
  std::uint16_t state = module_state::kProperModule;
  std::vector<ModuleDiffSubmodule> submodules;
};
struct ModuleDiffApi {
  std::uint32_t api = 0;
  std::vector<ModuleDiffModule> modules;
};
// ModuleDiffBlock 0x8104.
struct ModuleDiffBlock {
  std::vector<ModuleDiffApi> apis;
};
// ARServerBlock 0x8106 (the device's station name).
struct ArServerBlock {
  std::string station_name;
};

// ARRPCBlockReq 0x0107: the controller's RPC server port.
struct ArRpcBlockReq {
  std::uint16_t initiator_rpc_server_port = kRpcUdpPort;
};

// The whole Connect request (blocks in the order of IEC 61158-6-10
// IODConnectReq: ARBlockReq, IOCRBlockReq*, AlarmCRBlockReq,
// ExpectedSubmoduleBlockReq*, [ARRPCBlockReq]). A decoder takes the blocks
// in any order (controllers put the ExpectedSubmoduleBlockReqs before the
// AlarmCRBlockReq too) and counts the AlarmCRBlockReqs (the device refuses
// other than one, as p-net does); the encoder writes `alarm_cr`
// `alarm_cr_blocks` times.
struct ConnectRequest {
  ArBlockReq ar;
  std::vector<IocrBlockReq> iocrs;
  AlarmCrBlockReq alarm_cr;
  std::uint16_t alarm_cr_blocks = 1;
  std::vector<ExpectedSubmoduleBlockReq> expected;
  std::optional<ArRpcBlockReq> ar_rpc{};
};
// The whole Connect response (IODConnectRes: ARBlockRes, IOCRBlockRes*,
// AlarmCRBlockRes, ModuleDiffBlock (only when something differs),
// ARServerBlock). On refusal the body carries only the PNIOStatus.
struct ConnectResponse {
  ArBlockRes ar;
  std::vector<IocrBlockRes> iocrs;
  AlarmCrBlockRes alarm_cr;
  std::optional<ModuleDiffBlock> module_diff;
  std::optional<ArServerBlock> ar_server;
};

// The NDR args (blocks) of a Connect request/response.
std::vector<std::uint8_t> encode_connect_request(const ConnectRequest& req);
std::vector<std::uint8_t> encode_connect_response(const ConnectResponse& res);
// Decode the args; refuse unknown block types, wrong versions, lengths
// that disagree, a missing or second ARBlockReq (a response: a missing
// ARBlockRes or AlarmCRBlockRes).
WireStatus decode_connect_request(std::span<const std::uint8_t> args, ConnectRequest& out);
WireStatus decode_connect_response(std::span<const std::uint8_t> args, ConnectResponse& out);

// Single blocks (each encoder appends header + body).
void encode_block(ByteBuilder& b, const ArBlockReq& v);
void encode_block(ByteBuilder& b, const ArBlockRes& v);
void encode_block(ByteBuilder& b, const IocrBlockReq& v);
void encode_block(ByteBuilder& b, const IocrBlockRes& v);
void encode_block(ByteBuilder& b, const AlarmCrBlockReq& v);
void encode_block(ByteBuilder& b, const AlarmCrBlockRes& v);
void encode_block(ByteBuilder& b, const ExpectedSubmoduleBlockReq& v);
void encode_block(ByteBuilder& b, const ModuleDiffBlock& v);
void encode_block(ByteBuilder& b, const ArServerBlock& v);
void encode_block(ByteBuilder& b, const ArRpcBlockReq& v);
WireStatus decode_block(const BlockView& v, ArBlockReq& out);
WireStatus decode_block(const BlockView& v, ArBlockRes& out);
WireStatus decode_block(const BlockView& v, IocrBlockReq& out);
WireStatus decode_block(const BlockView& v, IocrBlockRes& out);
WireStatus decode_block(const BlockView& v, AlarmCrBlockReq& out);
WireStatus decode_block(const BlockView& v, AlarmCrBlockRes& out);
WireStatus decode_block(const BlockView& v, ExpectedSubmoduleBlockReq& out);
WireStatus decode_block(const BlockView& v, ModuleDiffBlock& out);
WireStatus decode_block(const BlockView& v, ArServerBlock& out);
WireStatus decode_block(const BlockView& v, ArRpcBlockReq& out);

// --- Record read / write ------------------------------------------------------

namespace record {
inline constexpr std::uint16_t kIndexMultipleWrite = 0xE040;
inline constexpr std::uint32_t kApiMultipleWrite =
    0xFFFFFFFF;  // API/slot/subslot of the outer header
inline constexpr std::uint16_t kSlotMultipleWrite = 0xFFFF;
inline constexpr std::uint16_t kSubslotMultipleWrite = 0xFFFF;
}  // namespace record

// IODWriteReqHeader 0x0008 / IODReadReqHeader 0x0009 (same fields; the
// 24 bytes of RWPadding follow; a read of an implicit AR carries a
// TargetARUUID, not supported here).
struct RecordRequestHeader {
  std::uint16_t seq_number = 0;
  Uuid ar_uuid;
  std::uint32_t api = 0;
  std::uint16_t slot = 0;
  std::uint16_t subslot = 0;
  std::uint16_t index = 0;
  std::uint32_t record_data_length = 0;  // write: data bytes; read: max bytes wanted
};
// IODWriteResHeader 0x8008 / IODReadResHeader 0x8009.
struct RecordResponseHeader {
  std::uint16_t seq_number = 0;
  Uuid ar_uuid;
  std::uint32_t api = 0;
  std::uint16_t slot = 0;
  std::uint16_t subslot = 0;
  std::uint16_t index = 0;
  std::uint32_t record_data_length = 0;
  std::uint16_t additional_value1 = 0;
  std::uint16_t additional_value2 = 0;
  PnioStatus status;  // write only (a read carries it in the NDR header)
};
void encode_block(ByteBuilder& b, std::uint16_t type, const RecordRequestHeader& h);
void encode_block(ByteBuilder& b, std::uint16_t type, const RecordResponseHeader& h);
WireStatus decode_block(const BlockView& v, RecordRequestHeader& out);   // 0x0008/0x0009
WireStatus decode_block(const BlockView& v, RecordResponseHeader& out);  // 0x8008/0x8009

// One record of a write.
struct RecordWrite {
  std::uint32_t api = 0;
  std::uint16_t slot = 0;
  std::uint16_t subslot = 0;
  std::uint16_t index = 0;
  std::vector<std::uint8_t> data;
};
// Write request args: one IODWriteReqHeader + data; or, for more than one
// record (or `force_multiple`), a MultipleWrite 0xE040 whose data is the
// records each with its own header, padded to 4-byte alignment between
// records (not after the last one).
std::vector<std::uint8_t> encode_write_request(std::uint16_t seq_number, const Uuid& ar_uuid,
                                               std::span<const RecordWrite> records,
                                               bool force_multiple = false);
// One record, not as MultipleWrite (the same bytes as encode_write_request()
// with that one record), into `out`: cleared first, capacity kept (a reused
// buffer allocates nothing, rpc.hpp: the *_to() twins). `h` names the
// record; its RecordDataLength is taken from `data`.
void encode_write_request_to(std::vector<std::uint8_t>& out, const RecordRequestHeader& h,
                             std::span<const std::uint8_t> data);
struct WriteRequest {
  RecordRequestHeader header;                    // the outer header (index 0xE040 for multiple)
  std::span<const std::uint8_t> data;            // single write: the record data
  std::vector<RecordRequestHeader> sub_headers;  // multiple write: each record's header
  std::vector<std::span<const std::uint8_t>> sub_data;
  [[nodiscard]] bool multiple() const { return header.index == record::kIndexMultipleWrite; }
};
WireStatus decode_write_request(std::span<const std::uint8_t> args, WriteRequest& out);
// Write response: outer IODWriteResHeader, and for a MultipleWrite one
// IODWriteResHeader per record (padded likewise).
struct WriteResponse {
  RecordResponseHeader header;
  std::vector<RecordResponseHeader> sub_results;
};
std::vector<std::uint8_t> encode_write_response(const WriteResponse& res);
void encode_write_response_to(std::vector<std::uint8_t>& out, const WriteResponse& res);
WireStatus decode_write_response(std::span<const std::uint8_t> args, WriteResponse& out);

// Read request args (IODReadReqHeader) and response (IODReadResHeader + data).
std::vector<std::uint8_t> encode_read_request(const RecordRequestHeader& h);
void encode_read_request_to(std::vector<std::uint8_t>& out, const RecordRequestHeader& h);
WireStatus decode_read_request(std::span<const std::uint8_t> args, RecordRequestHeader& out);
std::vector<std::uint8_t> encode_read_response(const RecordResponseHeader& h,
                                               std::span<const std::uint8_t> data);
void encode_read_response_to(std::vector<std::uint8_t>& out, const RecordResponseHeader& h,
                             std::span<const std::uint8_t> data);
WireStatus decode_read_response(std::span<const std::uint8_t> args, RecordResponseHeader& out,
                                std::span<const std::uint8_t>& data);

// --- Control (PrmEnd, ApplicationReady, Release) ------------------------------

namespace control {
inline constexpr std::uint16_t kPrmEnd = 0x0001;
inline constexpr std::uint16_t kApplicationReady = 0x0002;
inline constexpr std::uint16_t kRelease = 0x0004;
inline constexpr std::uint16_t kDone = 0x0008;
}  // namespace control
// IODControlReq/Res, IOXControlReq/Res, IODReleaseReq/Res (block types
// 0x0110/0x8110, 0x0112/0x8112, 0x0114/0x8114): Reserved (2), ARUUID,
// SessionKey, Reserved (2), ControlCommand, ControlBlockProperties.
struct ControlBlock {
  std::uint16_t block_type = block::kPrmEndReq;
  Uuid ar_uuid;
  std::uint16_t session_key = 0;
  std::uint16_t command = control::kPrmEnd;
  std::uint16_t properties = 0;
};
std::vector<std::uint8_t> encode_control(const ControlBlock& c);
void encode_block(ByteBuilder& b, const ControlBlock& c);
// Accepts any of the six control block types; the caller checks which.
WireStatus decode_control(std::span<const std::uint8_t> args, ControlBlock& out);
// The response block a device/controller answers `req` with (type | 0x8000,
// same ARUUID and session key, command DONE).
ControlBlock control_response_for(const ControlBlock& req);

}  // namespace plc::profinet

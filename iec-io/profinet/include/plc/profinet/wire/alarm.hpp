// Alarms over the RTA protocol (IEC 61158-6-10 §4.9 "RTA", §5.2.4 alarm
// blocks) on FrameID 0xFC01 (high) / 0xFE01 (low):
//   FrameID | AlarmDstEndpoint (2) | AlarmSrcEndpoint (2) |
//   PDUType (1: bits 0..3 type DATA 1, NACK 2, ACK 3, ERR 4; bits 4..7 version 1) |
//   AddFlags (1: bits 0..3 WindowSize = 1, bit 4 TACK) |
//   SendSeqNum (2) | AckSeqNum (2) | VarPartLen (2) | RTA-SDU
// The endpoints are the AlarmCR LocalAlarmReferences (destination = the
// receiver's). Sequence numbers run 0..0x7FFF and wrap; both start at 0xFFFF
// ("nothing sent/acknowledged yet"), so the first DATA carries 0.
// DATA-RTA carries an AlarmNotification (device -> controller) or an
// AlarmAck (controller -> device); each DATA-RTA is answered by an ACK-RTA.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "plc/profinet/wire/blocks.hpp"
#include "plc/profinet/wire/codec.hpp"
#include "plc/profinet/wire/ethernet.hpp"

namespace plc::profinet {

namespace rta {
inline constexpr std::uint8_t kTypeData = 1;
inline constexpr std::uint8_t kTypeNack = 2;
inline constexpr std::uint8_t kTypeAck = 3;
inline constexpr std::uint8_t kTypeErr = 4;
inline constexpr std::uint8_t kVersion = 1;
inline constexpr std::uint8_t kAddFlagsWindow1 = 0x01;
inline constexpr std::uint8_t kAddFlagTack = 0x10;
inline constexpr std::uint16_t kSeqInitial = 0xFFFF;
inline constexpr std::size_t kHeaderLength = 12;  // after the FrameID
[[nodiscard]] constexpr std::uint16_t next_seq(std::uint16_t s) {
  return static_cast<std::uint16_t>((s + 1) & 0x7FFF);
}
}  // namespace rta

namespace alarm_type {
inline constexpr std::uint16_t kDiagnosis = 0x0001;
inline constexpr std::uint16_t kProcess = 0x0002;
inline constexpr std::uint16_t kPull = 0x0003;
inline constexpr std::uint16_t kPlug = 0x0004;
inline constexpr std::uint16_t kStatus = 0x0005;
inline constexpr std::uint16_t kUpdate = 0x0006;
inline constexpr std::uint16_t kDiagnosisDisappears = 0x000C;
inline constexpr std::uint16_t kPlugWrong = 0x000A;
}  // namespace alarm_type
// AlarmSpecifier: bits 0..10 SequenceNumber, bit 11 ChannelDiagnosis,
// bit 12 ManufacturerSpecificDiagnosis, bit 13 SubmoduleDiagnosisState,
// bit 15 ARDiagnosisState.
namespace alarm_specifier {
inline constexpr std::uint16_t kSequenceMask = 0x07FF;
inline constexpr std::uint16_t kChannelDiagnosis = 0x0800;
inline constexpr std::uint16_t kManufacturerDiagnosis = 0x1000;
inline constexpr std::uint16_t kSubmoduleDiagnosisState = 0x2000;
inline constexpr std::uint16_t kArDiagnosisState = 0x8000;
}  // namespace alarm_specifier
// UserStructureIdentifier values: 0x8000 ChannelDiagnosis, 0x8002
// ExtChannelDiagnosis, 0x0000..0x7FFF manufacturer specific.
inline constexpr std::uint16_t kUsiChannelDiagnosis = 0x8000;

// AlarmNotification-PDU 0x0001 (high) / 0x0002 (low).
struct AlarmNotification {
  bool high_priority = false;
  std::uint16_t alarm_type = alarm_type::kDiagnosis;
  std::uint32_t api = 0;
  std::uint16_t slot = 0;
  std::uint16_t subslot = 0;
  std::uint32_t module_ident = 0;
  std::uint32_t submodule_ident = 0;
  std::uint16_t alarm_specifier = 0;
  std::optional<std::uint16_t> user_structure_identifier;  // with `data` after it
  std::vector<std::uint8_t> data;
};
// AlarmAck-PDU 0x8001 (high) / 0x8002 (low).
struct AlarmAck {
  bool high_priority = false;
  std::uint16_t alarm_type = alarm_type::kDiagnosis;
  std::uint32_t api = 0;
  std::uint16_t slot = 0;
  std::uint16_t subslot = 0;
  std::uint16_t alarm_specifier = 0;
  PnioStatus status;
};
// The ack a controller returns for a notification (same type, address and
// specifier; status OK).
AlarmAck ack_for(const AlarmNotification& n);

struct RtaHeader {
  std::uint16_t dst_endpoint = 0;
  std::uint16_t src_endpoint = 0;
  std::uint8_t pdu_type = rta::kTypeData;  // low nibble; the version nibble is added/checked
  std::uint8_t add_flags = rta::kAddFlagsWindow1 | rta::kAddFlagTack;
  std::uint16_t send_seq = 0;
  std::uint16_t ack_seq = rta::kSeqInitial;
};
// A decoded RTA PDU. For DATA, exactly one of the two blocks is set; for
// ERR, `status` holds the PNIOStatus.
struct RtaPdu {
  std::uint16_t frame_id = frame_id::kAlarmLow;
  RtaHeader header;
  std::optional<AlarmNotification> notification;
  std::optional<AlarmAck> ack;
  std::optional<PnioStatus> error;
};
// Decodes the PDU after the FrameID (0xFC01/0xFE01): version 1, a known
// type, VarPartLen within the bytes and 0 for ACK/NACK, a DATA carrying an
// alarm block whose priority fits the FrameID.
WireStatus decode_rta(std::uint16_t frame_id, std::span<const std::uint8_t> pdu, RtaPdu& out);

// Whole Ethernet frames.
std::vector<std::uint8_t> encode_alarm_notification(const Mac& dst, const Mac& src,
                                                    const RtaHeader& h, const AlarmNotification& n,
                                                    std::optional<std::uint16_t> vlan_tci = {});
std::vector<std::uint8_t> encode_alarm_ack(const Mac& dst, const Mac& src, const RtaHeader& h,
                                           const AlarmAck& a,
                                           std::optional<std::uint16_t> vlan_tci = {});
// ACK-RTA / NACK-RTA (no SDU): h.pdu_type says which. `high` picks 0xFC01.
std::vector<std::uint8_t> encode_rta_ack(const Mac& dst, const Mac& src, bool high,
                                         const RtaHeader& h,
                                         std::optional<std::uint16_t> vlan_tci = {});
// ERR-RTA with a PNIOStatus (aborts the AR).
std::vector<std::uint8_t> encode_rta_error(const Mac& dst, const Mac& src, bool high,
                                           const RtaHeader& h, const PnioStatus& status,
                                           std::optional<std::uint16_t> vlan_tci = {});

}  // namespace plc::profinet

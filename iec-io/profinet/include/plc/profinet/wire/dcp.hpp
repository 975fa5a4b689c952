// DCP, the Discovery and basic Configuration Protocol (IEC 61158-6-10
// §4.3, "DCP"), on FrameIDs 0xFEFC..0xFEFF:
//   FrameID | ServiceID (1) | ServiceType (1) | Xid (4) |
//   ResponseDelayFactor (2; Identify request, else reserved 0) |
//   DCPDataLength (2) | blocks
// block: Option (1) | Suboption (1) | DCPBlockLength (2) |
//   [BlockInfo (2) in responses/Hello; BlockQualifier (2) in Set requests] |
//   data | pad to an even length (the pad is not counted in DCPBlockLength
//   but is in DCPDataLength, after the last block too; decoding takes the
//   pad counted or not).
// Services: Get 3, Set 4, Identify 5, Hello 6. ServiceType: 0 request,
// 1 response success, 5 response "not supported".
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "plc/profinet/wire/codec.hpp"
#include "plc/profinet/wire/ethernet.hpp"

namespace plc::profinet {

namespace dcp {
inline constexpr std::uint8_t kServiceGet = 3;
inline constexpr std::uint8_t kServiceSet = 4;
inline constexpr std::uint8_t kServiceIdentify = 5;
inline constexpr std::uint8_t kServiceHello = 6;
inline constexpr std::uint8_t kTypeRequest = 0;
inline constexpr std::uint8_t kTypeResponseSuccess = 1;
inline constexpr std::uint8_t kTypeResponseUnsupported = 5;

// Options and suboptions (IEC 61158-6-10 Table "Option and Suboption").
inline constexpr std::uint8_t kOptIp = 1;
inline constexpr std::uint8_t kSubIpMac = 1;
inline constexpr std::uint8_t kSubIpParameter = 2;  // ip, netmask, gateway
inline constexpr std::uint8_t kSubIpFullSuite = 3;
inline constexpr std::uint8_t kOptDevice = 2;
inline constexpr std::uint8_t kSubDeviceVendor = 1;  // TypeOfStation (text)
inline constexpr std::uint8_t kSubDeviceNameOfStation = 2;
inline constexpr std::uint8_t kSubDeviceId = 3;  // VendorID, DeviceID
inline constexpr std::uint8_t kSubDeviceRole = 4;
inline constexpr std::uint8_t kSubDeviceOptions = 5;
inline constexpr std::uint8_t kSubDeviceAlias = 6;
inline constexpr std::uint8_t kSubDeviceInstance = 7;
inline constexpr std::uint8_t kOptDhcp = 3;
inline constexpr std::uint8_t kOptControl = 5;
inline constexpr std::uint8_t kSubControlStart = 1;
inline constexpr std::uint8_t kSubControlStop = 2;
inline constexpr std::uint8_t kSubControlSignal = 3;
inline constexpr std::uint8_t kSubControlResponse = 4;
inline constexpr std::uint8_t kSubControlFactoryReset = 5;
inline constexpr std::uint8_t kSubControlResetToFactory = 6;
inline constexpr std::uint8_t kOptDeviceInitiative = 6;
inline constexpr std::uint8_t kSubDeviceInitiative = 1;
inline constexpr std::uint8_t kOptAll = 0xFF;
inline constexpr std::uint8_t kSubAll = 0xFF;

// BlockQualifier of Set: bit 0 = store permanently.
inline constexpr std::uint16_t kQualifierTemporary = 0;
inline constexpr std::uint16_t kQualifierPermanent = 1;
// BlockInfo of the IP block: bit 0 "IP set", bit 1 "IP set by DHCP", bit 7 conflict.
inline constexpr std::uint16_t kIpInfoSet = 0x0001;
// BlockError of a Control/Response block.
inline constexpr std::uint8_t kErrorOk = 0;
inline constexpr std::uint8_t kErrorOptionUnsupported = 1;
inline constexpr std::uint8_t kErrorSuboptionUnsupported = 2;
inline constexpr std::uint8_t kErrorSuboptionNotSet = 3;
inline constexpr std::uint8_t kErrorResource = 4;
inline constexpr std::uint8_t kErrorSetNotPossible = 5;
// DeviceRole bit 0: IO device; bit 1: IO controller.
inline constexpr std::uint8_t kRoleDevice = 0x01;
inline constexpr std::uint8_t kRoleController = 0x02;
// The default ResponseDelayFactor of an Identify-all request (the device
// answers after (MAC mod factor) x 10 ms).
inline constexpr std::uint16_t kDefaultResponseDelay = 1;
}  // namespace dcp

// One DCP block as it is on the wire. `info` is BlockInfo (responses,
// Hello) or BlockQualifier (Set request); absent in Identify/Get requests
// and in Control/Response blocks.
struct DcpBlock {
  std::uint8_t option = 0;
  std::uint8_t suboption = 0;
  std::optional<std::uint16_t> info;
  std::vector<std::uint8_t> data;
};

// A whole DCP PDU after the FrameID.
struct DcpMessage {
  std::uint16_t frame_id = 0;
  std::uint8_t service_id = 0;
  std::uint8_t service_type = 0;
  std::uint32_t xid = 0;
  std::uint16_t response_delay = 0;
  std::vector<DcpBlock> blocks;
  [[nodiscard]] const DcpBlock* find(std::uint8_t option, std::uint8_t suboption) const;
};

// IPv4 addresses in host order (0xC0A80001 = 192.168.0.1).
struct DcpIpSuite {
  std::uint32_t ip = 0;
  std::uint32_t netmask = 0;
  std::uint32_t gateway = 0;
};

// What a device tells about itself (Identify response, Hello), or the
// subset Get/Set transport.
struct DcpIdentity {
  std::string station_name;     // NameOfStation (may be empty: not named yet)
  std::string type_of_station;  // DeviceVendorValue, e.g. "HIWIN E1"
  std::uint16_t vendor_id = 0;
  std::uint16_t device_id = 0;
  std::uint8_t device_role = dcp::kRoleDevice;
  DcpIpSuite ip;
  std::uint16_t ip_info = dcp::kIpInfoSet;
  std::optional<std::uint16_t> device_instance;  // high byte, low byte
};

// A Set request: what to set (any of them), and whether permanently.
struct DcpSetRequest {
  std::optional<std::string> station_name;
  std::optional<DcpIpSuite> ip;
  bool signal = false;         // Control/Signal (flash the LED)
  bool reset_factory = false;  // Control/ResetToFactory (mode 2: all)
  bool permanent = true;
};

// Result of one option in a Set response (Control/Response block data).
struct DcpSetResult {
  std::uint8_t option = 0;
  std::uint8_t suboption = 0;
  std::uint8_t error = dcp::kErrorOk;
};

// --- decoding -------------------------------------------------------------

// Decodes the DCP PDU that follows the FrameID (`frame_id` from
// decode_pn_frame). Refuses unknown services, DCPDataLength beyond the
// bytes, blocks that overrun, and FrameIDs outside 0xFEFC..0xFEFF.
WireStatus decode_dcp(std::uint16_t frame_id, std::span<const std::uint8_t> pdu, DcpMessage& out);

// Interprets the blocks of an Identify response / Hello / Get response.
// Refuses a NameOfStation that is not a valid station name (IEC 61158-6-10
// §4.3.1.4.16: labels of a-z0-9 and '-', <= 63 per label, <= 240 in all).
WireStatus identity_from(const DcpMessage& m, DcpIdentity& out);
// Interprets the blocks of a Set request.
WireStatus set_request_from(const DcpMessage& m, DcpSetRequest& out);
// Interprets the Control/Response blocks of a Set response.
WireStatus set_results_from(const DcpMessage& m, std::vector<DcpSetResult>& out);
// The station-name filter of an Identify request (empty: identify all).
std::optional<std::string> identify_filter(const DcpMessage& m);

// The station-name rule of IEC 61158-6-10 (also used by the controller to
// check its config).
[[nodiscard]] bool valid_station_name(std::string_view name);

// --- encoding: whole Ethernet frames (header + DCP PDU, padded) ----------

// Identify request to the multicast address: all devices, or only the one
// named `station_name`.
std::vector<std::uint8_t> encode_dcp_identify_request(
    const Mac& src, std::uint32_t xid, std::optional<std::string_view> station_name,
    std::uint16_t response_delay = dcp::kDefaultResponseDelay);
// Identify response (unicast to the requester).
std::vector<std::uint8_t> encode_dcp_identify_response(const Mac& dst, const Mac& src,
                                                       std::uint32_t xid, const DcpIdentity& id);
// Hello (multicast, FrameID 0xFEFC), the device's announcement.
std::vector<std::uint8_t> encode_dcp_hello(const Mac& src, std::uint32_t xid,
                                           const DcpIdentity& id);
// Set request (FrameID 0xFEFD) and its response.
std::vector<std::uint8_t> encode_dcp_set_request(const Mac& dst, const Mac& src, std::uint32_t xid,
                                                 const DcpSetRequest& req);
std::vector<std::uint8_t> encode_dcp_set_response(const Mac& dst, const Mac& src, std::uint32_t xid,
                                                  std::span<const DcpSetResult> results);
// Get request for the listed (option, suboption) pairs, and its response
// (the identity's matching blocks; unknown ones answered "not supported").
std::vector<std::uint8_t> encode_dcp_get_request(
    const Mac& dst, const Mac& src, std::uint32_t xid,
    std::span<const std::pair<std::uint8_t, std::uint8_t>> options);
std::vector<std::uint8_t> encode_dcp_get_response(
    const Mac& dst, const Mac& src, std::uint32_t xid, const DcpIdentity& id,
    std::span<const std::pair<std::uint8_t, std::uint8_t>> options);

// Lower level: the DCP PDU of a DcpMessage (after the FrameID).
std::vector<std::uint8_t> encode_dcp(const DcpMessage& m);

}  // namespace plc::profinet

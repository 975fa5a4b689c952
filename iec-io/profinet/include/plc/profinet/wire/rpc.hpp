// DCE/RPC connectionless (CL) PDUs as PROFINET IO uses them over UDP 34964
// (IEC 61158-6-10 §4.10.3 "RPC", DCE 1.1 RPC chapter 12):
//   80-byte CL header | NDR header (20 bytes) | PROFINET blocks
// The header's multi-byte fields and UUIDs are in the byte order its drep
// says (we send little-endian, drep[0] = 0x10; we accept both); the UUIDs
// inside the PROFINET blocks are always big-endian.
// NDR request:  ArgsMaximum, ArgsLength, MaximumCount, Offset, ActualCount
// NDR response: PNIOStatus (4 bytes), ArgsLength, MaximumCount, Offset, ActualCount
// (each u32 in drep byte order; MaximumCount = ArgsMaximum (request) and
// ActualCount = ArgsLength, Offset 0).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "plc/profinet/wire/codec.hpp"

namespace plc::profinet {

inline constexpr std::uint16_t kRpcUdpPort = 34964;  // 0x8894

// A UUID as its fields (RFC 4122 / DCE): data1-data2-data3-data4[8].
struct Uuid {
  std::uint32_t data1 = 0;
  std::uint16_t data2 = 0;
  std::uint16_t data3 = 0;
  std::array<std::uint8_t, 8> data4{};
  friend bool operator==(const Uuid&, const Uuid&) = default;
  [[nodiscard]] bool is_nil() const { return *this == Uuid{}; }
  // "dea00001-6c97-11d1-8271-00a02442df7d"
  [[nodiscard]] std::string to_string() const;
  // Parses the form above; false on anything else.
  static bool parse(std::string_view text, Uuid& out);
};
// Big-endian (blocks) or drep-ordered (RPC header) 16 bytes.
void put_uuid(ByteBuilder& b, const Uuid& u, bool little_endian = false);
Uuid get_uuid(ByteReader& r, bool little_endian = false);
// A random (version 4) UUID from the given 128 random bits (the caller owns
// the randomness, so virtual-time runs stay reproducible).
Uuid make_uuid_v4(std::uint64_t hi, std::uint64_t lo);

// PROFINET IO interface UUIDs (IEC 61158-6-10 Table "Interface UUIDs").
inline constexpr Uuid kPnioDeviceInterface{
    0xDEA00001, 0x6C97, 0x11D1, {0x82, 0x71, 0x00, 0xA0, 0x24, 0x42, 0xDF, 0x7D}};
inline constexpr Uuid kPnioControllerInterface{
    0xDEA00002, 0x6C97, 0x11D1, {0x82, 0x71, 0x00, 0xA0, 0x24, 0x42, 0xDF, 0x7D}};
// The object UUID of a PROFINET IO entity:
// DEA00000-6C97-11D1-8271-{instance:2}{device id:2}{vendor id:2}.
Uuid pnio_object_uuid(std::uint16_t instance, std::uint16_t device_id, std::uint16_t vendor_id);

namespace rpc {
inline constexpr std::uint8_t kVersion = 4;
// Packet types (DCE 1.1 §12.5.3.1).
inline constexpr std::uint8_t kRequest = 0;
inline constexpr std::uint8_t kPing = 1;
inline constexpr std::uint8_t kResponse = 2;
inline constexpr std::uint8_t kFault = 3;
inline constexpr std::uint8_t kWorking = 4;
inline constexpr std::uint8_t kNoCall = 5;
inline constexpr std::uint8_t kReject = 6;
inline constexpr std::uint8_t kAck = 7;
inline constexpr std::uint8_t kCancel = 8;
inline constexpr std::uint8_t kFack = 9;
inline constexpr std::uint8_t kCancelAck = 10;
// flags1
inline constexpr std::uint8_t kFlagLastFragment = 0x02;
inline constexpr std::uint8_t kFlagFragment = 0x04;
inline constexpr std::uint8_t kFlagNoFack = 0x08;
inline constexpr std::uint8_t kFlagMaybe = 0x10;
inline constexpr std::uint8_t kFlagIdempotent = 0x20;
inline constexpr std::uint8_t kFlagBroadcast = 0x40;
// PROFINET IO operations (opnum).
inline constexpr std::uint16_t kOpConnect = 0;
inline constexpr std::uint16_t kOpRelease = 1;
inline constexpr std::uint16_t kOpRead = 2;
inline constexpr std::uint16_t kOpWrite = 3;
inline constexpr std::uint16_t kOpControl = 4;
inline constexpr std::uint16_t kOpReadImplicit = 5;
inline constexpr std::size_t kHeaderLength = 80;
inline constexpr std::size_t kNdrHeaderLength = 20;
// The largest body we accept/send in one (unfragmented) datagram.
inline constexpr std::uint32_t kMaxArgs = 1432;
}  // namespace rpc

// The 80-byte CL header. `little_endian` is drep[0] bit 4 (integer
// representation); character set ASCII and IEEE floats are assumed.
struct RpcHeader {
  std::uint8_t packet_type = rpc::kRequest;
  std::uint8_t flags1 = rpc::kFlagIdempotent;
  std::uint8_t flags2 = 0;
  bool little_endian = true;
  Uuid object;
  Uuid interface;
  Uuid activity;
  std::uint32_t server_boot_time = 0;
  std::uint32_t interface_version = 1;
  std::uint32_t sequence_number = 0;
  std::uint16_t opnum = 0;
  std::uint16_t interface_hint = 0xFFFF;
  std::uint16_t activity_hint = 0xFFFF;
  std::uint16_t body_length = 0;  // set by the encoder
  std::uint16_t fragment_number = 0;
  std::uint8_t auth_protocol = 0;
  std::uint8_t serial = 0;
};

// PNIOStatus (IEC 61158-6-10 "PNIOStatus"): ErrorCode, ErrorDecode,
// ErrorCode1, ErrorCode2; all zero = OK.
struct PnioStatus {
  std::uint8_t error_code = 0;
  std::uint8_t error_decode = 0;
  std::uint8_t error_code1 = 0;
  std::uint8_t error_code2 = 0;
  [[nodiscard]] bool ok() const {
    return error_code == 0 && error_decode == 0 && error_code1 == 0 && error_code2 == 0;
  }
  [[nodiscard]] std::uint32_t value() const {
    return (std::uint32_t{error_code} << 24) | (std::uint32_t{error_decode} << 16) |
           (std::uint32_t{error_code1} << 8) | error_code2;
  }
  static PnioStatus from(std::uint32_t v) {
    return {static_cast<std::uint8_t>(v >> 24), static_cast<std::uint8_t>(v >> 16),
            static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v)};
  }
  friend bool operator==(const PnioStatus&, const PnioStatus&) = default;
};
// PNIOStatus on the wire: four single octets (so drep does not apply).
void put_pnio_status(ByteBuilder& b, const PnioStatus& s);
PnioStatus get_pnio_status(ByteReader& r);

namespace pnio_error {
// ErrorCode
inline constexpr std::uint8_t kCodePnio = 0x81;      // IODConnectRes etc.
inline constexpr std::uint8_t kCodeRta = 0xCF;       // RTA error (alarms)
inline constexpr std::uint8_t kCodeAlarmAck = 0xDA;  // AlarmAck
inline constexpr std::uint8_t kCodeConnect = 0xDB;   // IODConnectRes
inline constexpr std::uint8_t kCodeRelease = 0xDC;
inline constexpr std::uint8_t kCodeControl = 0xDD;
inline constexpr std::uint8_t kCodeRead = 0xDE;
inline constexpr std::uint8_t kCodeWrite = 0xDF;
// ErrorDecode
inline constexpr std::uint8_t kDecodePnioRw = 0x80;  // record read/write (ErrorCode1 = class/code)
inline constexpr std::uint8_t kDecodePnio = 0x81;    // ErrorCode1 = block, ErrorCode2 = field
inline constexpr std::uint8_t kDecodeManufacturer = 0x82;
}  // namespace pnio_error

// A decoded CL PDU: header and body (views into the datagram).
struct RpcPdu {
  RpcHeader header;
  std::span<const std::uint8_t> body;
};
// Decodes and checks the CL header (version 4, a known packet type, body
// length within the datagram, not fragmented; fragmented PDUs are refused
// with reason "fragmented").
WireStatus decode_rpc(std::span<const std::uint8_t> datagram, RpcPdu& out);
// Header + body as one datagram (body_length taken from body).
std::vector<std::uint8_t> encode_rpc(const RpcHeader& h, std::span<const std::uint8_t> body);
// The *_to() twins of the encoders build the same bytes into `out`, which
// they clear first: its capacity is kept, so a buffer reused for every
// call (the controller's and PnDevice's record exchanges) allocates nothing
// once it has grown to the longest message. The vector-returning versions
// call them.
void encode_rpc_to(std::vector<std::uint8_t>& out, const RpcHeader& h,
                   std::span<const std::uint8_t> body);

// The NDR header of a PROFINET IO request/response body.
struct NdrRequest {
  std::uint32_t args_maximum = rpc::kMaxArgs;
  std::span<const std::uint8_t> args;  // the blocks (decode: view into the body)
};
struct NdrResponse {
  PnioStatus status;
  std::uint32_t args_maximum = 0;  // MaximumCount (echoes the request's ArgsMaximum)
  std::span<const std::uint8_t> args;
};
// Checks ArgsLength <= ArgsMaximum, ActualCount == ArgsLength, Offset 0 and
// that ArgsLength bytes follow.
WireStatus decode_ndr_request(std::span<const std::uint8_t> body, bool little_endian,
                              NdrRequest& out);
WireStatus decode_ndr_response(std::span<const std::uint8_t> body, bool little_endian,
                               NdrResponse& out);
std::vector<std::uint8_t> encode_ndr_request(std::uint32_t args_maximum,
                                             std::span<const std::uint8_t> args,
                                             bool little_endian = true);
std::vector<std::uint8_t> encode_ndr_response(const PnioStatus& status, std::uint32_t args_maximum,
                                              std::span<const std::uint8_t> args,
                                              bool little_endian = true);
void encode_ndr_request_to(std::vector<std::uint8_t>& out, std::uint32_t args_maximum,
                           std::span<const std::uint8_t> args, bool little_endian = true);
void encode_ndr_response_to(std::vector<std::uint8_t>& out, const PnioStatus& status,
                            std::uint32_t args_maximum, std::span<const std::uint8_t> args,
                            bool little_endian = true);

// The response header to a request: same object/interface/activity UUIDs,
// sequence number, opnum and drep; packet type response, flags1 fitting.
RpcHeader response_header_for(const RpcHeader& request);

// For the pcap only (the real stack sends over a UDP socket): a whole
// Ethernet/IPv4/UDP frame with correct IPv4 header and UDP checksums.
std::vector<std::uint8_t> wrap_udp_ipv4(const std::array<std::uint8_t, 6>& dst_mac,
                                        const std::array<std::uint8_t, 6>& src_mac,
                                        std::uint32_t src_ip, std::uint16_t src_port,
                                        std::uint32_t dst_ip, std::uint16_t dst_port,
                                        std::span<const std::uint8_t> payload,
                                        std::uint16_t ip_id = 0);

}  // namespace plc::profinet

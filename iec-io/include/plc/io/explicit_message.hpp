// DeviceNet explicit messages carried by the asynchronous record path.
//
// An FB reaches a DeviceNet object (class/instance/attribute) the same way it
// reaches a PROFINET record: it fills a RecordRequest, submits it through its
// DevicePort and polls it in later scans. The mapping is ours (the VF66B
// manual, toyo-vf66-devicenet.md §1.4/§1.5/§11.1, defines only the wire):
//
//  * every explicit service is a record READ that carries request bytes
//    (RecordRequest::prepare_read(index, request));
//  * index = kExplicitIndexBase | service code (0x0E Get_Attribute_Single,
//    0x10 Set_Attribute_Single, 0x05 Reset, ...);
//  * request bytes = class, instance (8/8 body format), then the attribute id
//    for the attribute services (0x0E, 0x10), then the service data;
//  * a success answer is the response's service data (for 0x0E the
//    attribute value, little-endian as on the wire; empty for 0x10/0x05);
//  * an Error Response (service 0x94) fails the request with device code
//    general_status << 8 | additional_code (0xFF when none), so
//    general_status(error_code()) gives the §11.1 code back.
//
// Under the in-process sim plugin a model sees the same request through
// DeviceModel::query_record; the DeviceNet scanner puts it on the wire.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace plc::io::explicit_msg {

inline constexpr std::uint16_t kExplicitIndexBase = 0xD000;

// Service codes (toyo-vf66-devicenet.md §1.5, [std]).
inline constexpr std::uint8_t kGetAttributesAll = 0x01;
inline constexpr std::uint8_t kReset = 0x05;
inline constexpr std::uint8_t kGetAttributeSingle = 0x0E;
inline constexpr std::uint8_t kSetAttributeSingle = 0x10;
inline constexpr std::uint8_t kErrorResponse = 0x14;
inline constexpr std::uint8_t kAllocateMasterSlave = 0x4B;
inline constexpr std::uint8_t kReleaseMasterSlave = 0x4C;

// General status codes of an Error Response (§11.1, Table 5.2).
inline constexpr std::uint8_t kResourceUnavailable = 0x02;
inline constexpr std::uint8_t kServiceNotSupported = 0x08;
inline constexpr std::uint8_t kInvalidAttributeValue = 0x09;
inline constexpr std::uint8_t kAlreadyInState = 0x0B;
inline constexpr std::uint8_t kObjectStateConflict = 0x0C;
inline constexpr std::uint8_t kAttributeNotSettable = 0x0E;
inline constexpr std::uint8_t kPrivilegeViolation = 0x0F;
inline constexpr std::uint8_t kDeviceStateConflict = 0x10;
inline constexpr std::uint8_t kReplyDataTooLarge = 0x11;
inline constexpr std::uint8_t kNotEnoughData = 0x13;
inline constexpr std::uint8_t kAttributeNotSupported = 0x14;
inline constexpr std::uint8_t kTooMuchData = 0x15;
inline constexpr std::uint8_t kObjectDoesNotExist = 0x16;
inline constexpr std::uint8_t kVendorSpecific = 0x1F;
inline constexpr std::uint8_t kInvalidParameter = 0x20;
inline constexpr std::uint8_t kNoAdditionalCode = 0xFF;

[[nodiscard]] constexpr std::uint16_t record_index(std::uint8_t service) {
  return static_cast<std::uint16_t>(kExplicitIndexBase | (service & 0x7F));
}
[[nodiscard]] constexpr bool is_explicit_index(std::uint16_t index) {
  return (index & 0xFF80) == kExplicitIndexBase;
}
[[nodiscard]] constexpr std::uint8_t service_of(std::uint16_t index) {
  return static_cast<std::uint8_t>(index & 0x7F);
}
// Services whose request names an attribute after class and instance.
[[nodiscard]] constexpr bool has_attribute(std::uint8_t service) {
  return service == kGetAttributeSingle || service == kSetAttributeSingle;
}

// The device code a failed request carries, and the §11.1 code back from it.
[[nodiscard]] constexpr std::uint16_t error_code(std::uint8_t general,
                                                 std::uint8_t additional = kNoAdditionalCode) {
  return static_cast<std::uint16_t>((general << 8) | additional);
}
[[nodiscard]] constexpr std::uint8_t general_status(std::uint16_t code) {
  return static_cast<std::uint8_t>(code >> 8);
}
[[nodiscard]] constexpr std::uint8_t additional_code(std::uint16_t code) {
  return static_cast<std::uint8_t>(code & 0xFF);
}

struct Path {
  std::uint8_t cls = 0;
  std::uint8_t instance = 0;
  std::uint8_t attribute = 0;  // only for has_attribute(service)
};

// Writes the request bytes (class, instance[, attribute], data) into `out`;
// returns the length, or 0 when they do not fit.
[[nodiscard]] inline std::size_t encode_request(std::uint8_t service, const Path& p,
                                                std::span<const std::uint8_t> data,
                                                std::span<std::uint8_t> out) {
  const std::size_t head = has_attribute(service) ? 3 : 2;
  if (out.size() < head + data.size()) return 0;
  out[0] = p.cls;
  out[1] = p.instance;
  if (head == 3) out[2] = p.attribute;
  for (std::size_t i = 0; i < data.size(); ++i) out[head + i] = data[i];
  return head + data.size();
}

struct Request {
  std::uint8_t service = 0;
  Path path{};
  std::span<const std::uint8_t> data{};
};

// Splits a record read's index and request bytes; nullopt when the index is
// not an explicit service or the request is too short for its path.
[[nodiscard]] inline std::optional<Request> decode_request(std::uint16_t index,
                                                           std::span<const std::uint8_t> req) {
  if (!is_explicit_index(index)) return std::nullopt;
  Request r;
  r.service = service_of(index);
  const std::size_t head = has_attribute(r.service) ? 3 : 2;
  if (req.size() < head) return std::nullopt;
  r.path.cls = req[0];
  r.path.instance = req[1];
  if (head == 3) r.path.attribute = req[2];
  r.data = req.subspan(head);
  return r;
}

}  // namespace plc::io::explicit_msg

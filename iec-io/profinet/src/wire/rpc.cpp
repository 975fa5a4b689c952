#include "plc/profinet/wire/rpc.hpp"

#include <cstdio>

namespace plc::profinet {

std::string Uuid::to_string() const {
  char s[40];
  std::snprintf(s, sizeof s, "%08x-%04x-%04x-%02x%02x-%02x%02x%02x%02x%02x%02x", data1, data2,
                data3, data4[0], data4[1], data4[2], data4[3], data4[4], data4[5], data4[6],
                data4[7]);
  return s;
}

bool Uuid::parse(std::string_view t, Uuid& out) {
  if (t.size() != 36 || t[8] != '-' || t[13] != '-' || t[18] != '-' || t[23] != '-') return false;
  std::uint8_t bytes[16];
  std::size_t n = 0;
  for (std::size_t i = 0; i < t.size();) {
    if (t[i] == '-') {
      ++i;
      continue;
    }
    auto hex = [](char c) -> int {
      if (c >= '0' && c <= '9') return c - '0';
      if (c >= 'a' && c <= 'f') return c - 'a' + 10;
      if (c >= 'A' && c <= 'F') return c - 'A' + 10;
      return -1;
    };
    const int hi = hex(t[i]), lo = i + 1 < t.size() ? hex(t[i + 1]) : -1;
    if (hi < 0 || lo < 0 || n >= 16) return false;
    bytes[n++] = static_cast<std::uint8_t>(hi * 16 + lo);
    i += 2;
  }
  if (n != 16) return false;
  ByteReader r(bytes);
  out = get_uuid(r);
  return true;
}

void put_uuid(ByteBuilder& b, const Uuid& u, bool le) {
  b.u32(u.data1, le);
  b.u16(u.data2, le);
  b.u16(u.data3, le);
  b.bytes(u.data4);
}

Uuid get_uuid(ByteReader& r, bool le) {
  Uuid u;
  u.data1 = r.u32(le);
  u.data2 = r.u16(le);
  u.data3 = r.u16(le);
  const auto d = r.bytes(8);
  if (d.size() == 8) std::copy(d.begin(), d.end(), u.data4.begin());
  return u;
}

Uuid make_uuid_v4(std::uint64_t hi, std::uint64_t lo) {
  Uuid u;
  u.data1 = static_cast<std::uint32_t>(hi >> 32);
  u.data2 = static_cast<std::uint16_t>(hi >> 16);
  u.data3 = static_cast<std::uint16_t>((hi & 0x0FFF) | 0x4000);  // version 4
  for (int i = 0; i < 8; ++i)
    u.data4[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(lo >> (56 - 8 * i));
  u.data4[0] = static_cast<std::uint8_t>((u.data4[0] & 0x3F) | 0x80);  // variant RFC 4122
  return u;
}

Uuid pnio_object_uuid(std::uint16_t instance, std::uint16_t device_id, std::uint16_t vendor_id) {
  return {
      0xDEA00000,
      0x6C97,
      0x11D1,
      {0x82, 0x71, static_cast<std::uint8_t>(instance >> 8), static_cast<std::uint8_t>(instance),
       static_cast<std::uint8_t>(device_id >> 8), static_cast<std::uint8_t>(device_id),
       static_cast<std::uint8_t>(vendor_id >> 8), static_cast<std::uint8_t>(vendor_id)}};
}

void put_pnio_status(ByteBuilder& b, const PnioStatus& s) {
  b.u8(s.error_code);
  b.u8(s.error_decode);
  b.u8(s.error_code1);
  b.u8(s.error_code2);
}

PnioStatus get_pnio_status(ByteReader& r) {
  PnioStatus s;
  s.error_code = r.u8();
  s.error_decode = r.u8();
  s.error_code1 = r.u8();
  s.error_code2 = r.u8();
  return s;
}

WireStatus decode_rpc(std::span<const std::uint8_t> d, RpcPdu& out) {
  if (d.size() < rpc::kHeaderLength) return wire_fail(WireError::Truncated, "RPC header truncated");
  ByteReader r(d);
  RpcHeader& h = out.header;
  const std::uint8_t version = r.u8();
  h.packet_type = r.u8() & 0x1F;
  h.flags1 = r.u8();
  h.flags2 = r.u8();
  const std::uint8_t drep0 = r.u8();
  r.skip(2);  // drep[1] float representation, drep[2] reserved
  h.little_endian = (drep0 & 0xF0) == 0x10;
  const bool le = h.little_endian;
  const std::uint8_t serial_hi = r.u8();
  h.object = get_uuid(r, le);
  h.interface = get_uuid(r, le);
  h.activity = get_uuid(r, le);
  h.server_boot_time = r.u32(le);
  h.interface_version = r.u32(le);
  h.sequence_number = r.u32(le);
  h.opnum = r.u16(le);
  h.interface_hint = r.u16(le);
  h.activity_hint = r.u16(le);
  h.body_length = r.u16(le);
  h.fragment_number = r.u16(le);
  h.auth_protocol = r.u8();
  h.serial = static_cast<std::uint8_t>(r.u8());
  (void)serial_hi;
  if (version != rpc::kVersion) return wire_fail(WireError::BadHeader, "RPC version not 4");
  if ((drep0 & 0xF0) > 0x10)
    return wire_fail(WireError::BadHeader, "unknown RPC data representation");
  if (h.packet_type > rpc::kCancelAck)
    return wire_fail(WireError::BadHeader, "unknown RPC packet type");
  if (h.flags1 & rpc::kFlagFragment) return wire_fail(WireError::BadHeader, "fragmented");
  if (h.auth_protocol != 0)
    return wire_fail(WireError::BadHeader, "RPC authentication not supported");
  if (h.body_length > r.remaining())
    return wire_fail(WireError::BadLength, "RPC body length beyond the datagram");
  out.body = r.bytes(h.body_length);
  return kWireOk;
}

std::vector<std::uint8_t> encode_rpc(const RpcHeader& h, std::span<const std::uint8_t> body) {
  std::vector<std::uint8_t> out;
  out.reserve(rpc::kHeaderLength + body.size());
  encode_rpc_to(out, h, body);
  return out;
}

void encode_rpc_to(std::vector<std::uint8_t>& out, const RpcHeader& h,
                   std::span<const std::uint8_t> body) {
  out.clear();
  ByteBuilder b(out);
  const bool le = h.little_endian;
  b.u8(rpc::kVersion);
  b.u8(h.packet_type);
  b.u8(h.flags1);
  b.u8(h.flags2);
  b.u8(le ? 0x10 : 0x00);  // integer representation; ASCII
  b.u8(0x00);              // IEEE float
  b.u8(0x00);
  b.u8(0x00);  // serial high
  put_uuid(b, h.object, le);
  put_uuid(b, h.interface, le);
  put_uuid(b, h.activity, le);
  b.u32(h.server_boot_time, le);
  b.u32(h.interface_version, le);
  b.u32(h.sequence_number, le);
  b.u16(h.opnum, le);
  b.u16(h.interface_hint, le);
  b.u16(h.activity_hint, le);
  b.u16(static_cast<std::uint16_t>(body.size()), le);
  b.u16(h.fragment_number, le);
  b.u8(h.auth_protocol);
  b.u8(h.serial);
  b.bytes(body);
}

namespace {
struct NdrArray {
  std::uint32_t maximum = 0, length = 0, max_count = 0, offset = 0, actual = 0;
};
WireStatus check_ndr(ByteReader& r, const NdrArray& a, std::span<const std::uint8_t>& args) {
  if (r.failed()) return wire_fail(WireError::Truncated, "NDR header truncated");
  if (a.offset != 0) return wire_fail(WireError::BadHeader, "NDR Offset not 0");
  if (a.actual != a.length) return wire_fail(WireError::BadLength, "NDR ActualCount != ArgsLength");
  if (a.length > a.max_count)
    return wire_fail(WireError::BadLength, "NDR ArgsLength > MaximumCount");
  if (a.length > r.remaining())
    return wire_fail(WireError::BadLength, "NDR ArgsLength beyond the body");
  args = r.bytes(a.length);
  return kWireOk;
}
}  // namespace

WireStatus decode_ndr_request(std::span<const std::uint8_t> body, bool le, NdrRequest& out) {
  ByteReader r(body);
  NdrArray a{r.u32(le), r.u32(le), r.u32(le), r.u32(le), r.u32(le)};
  out.args_maximum = a.maximum;
  if (!r.failed() && a.length > a.maximum)
    return wire_fail(WireError::BadLength, "NDR ArgsLength > ArgsMaximum");
  return check_ndr(r, a, out.args);
}

WireStatus decode_ndr_response(std::span<const std::uint8_t> body, bool le, NdrResponse& out) {
  ByteReader r(body);
  out.status = get_pnio_status(r);
  NdrArray a;
  a.length = r.u32(le);
  a.max_count = r.u32(le);
  a.offset = r.u32(le);
  a.actual = r.u32(le);
  out.args_maximum = a.max_count;
  return check_ndr(r, a, out.args);
}

std::vector<std::uint8_t> encode_ndr_request(std::uint32_t args_maximum,
                                             std::span<const std::uint8_t> args, bool le) {
  std::vector<std::uint8_t> out;
  encode_ndr_request_to(out, args_maximum, args, le);
  return out;
}

void encode_ndr_request_to(std::vector<std::uint8_t>& out, std::uint32_t args_maximum,
                           std::span<const std::uint8_t> args, bool le) {
  out.clear();
  ByteBuilder b(out);
  const auto len = static_cast<std::uint32_t>(args.size());
  b.u32(args_maximum, le);
  b.u32(len, le);
  b.u32(args_maximum, le);
  b.u32(0, le);
  b.u32(len, le);
  b.bytes(args);
}

std::vector<std::uint8_t> encode_ndr_response(const PnioStatus& s, std::uint32_t args_maximum,
                                              std::span<const std::uint8_t> args, bool le) {
  std::vector<std::uint8_t> out;
  encode_ndr_response_to(out, s, args_maximum, args, le);
  return out;
}

void encode_ndr_response_to(std::vector<std::uint8_t>& out, const PnioStatus& s,
                            std::uint32_t args_maximum, std::span<const std::uint8_t> args,
                            bool le) {
  out.clear();
  ByteBuilder b(out);
  const auto len = static_cast<std::uint32_t>(args.size());
  put_pnio_status(b, s);
  b.u32(len, le);
  b.u32(args_maximum, le);
  b.u32(0, le);
  b.u32(len, le);
  b.bytes(args);
}

RpcHeader response_header_for(const RpcHeader& req) {
  RpcHeader h = req;
  h.packet_type = rpc::kResponse;
  // A single-fragment response: last fragment, no fack wanted.
  h.flags1 = rpc::kFlagLastFragment | rpc::kFlagNoFack;
  h.flags2 = 0;
  h.fragment_number = 0;
  return h;
}

namespace {
std::uint32_t sum16(std::span<const std::uint8_t> d, std::uint32_t acc) {
  for (std::size_t i = 0; i + 1 < d.size(); i += 2) acc += std::uint32_t{d[i]} << 8 | d[i + 1];
  if (d.size() % 2) acc += std::uint32_t{d.back()} << 8;
  return acc;
}
std::uint16_t fold(std::uint32_t acc) {
  while (acc >> 16) acc = (acc & 0xFFFF) + (acc >> 16);
  return static_cast<std::uint16_t>(~acc);
}
}  // namespace

std::vector<std::uint8_t> wrap_udp_ipv4(const std::array<std::uint8_t, 6>& dst_mac,
                                        const std::array<std::uint8_t, 6>& src_mac,
                                        std::uint32_t src_ip, std::uint16_t src_port,
                                        std::uint32_t dst_ip, std::uint16_t dst_port,
                                        std::span<const std::uint8_t> payload,
                                        std::uint16_t ip_id) {
  std::vector<std::uint8_t> f;
  f.reserve(42 + payload.size() + 60);
  ByteBuilder b(f);
  b.bytes(dst_mac);
  b.bytes(src_mac);
  b.u16(0x0800);
  const std::size_t ip_at = b.pos();
  const auto udp_len = static_cast<std::uint16_t>(8 + payload.size());
  b.u8(0x45);  // IPv4, 20-byte header
  b.u8(0);
  b.u16(static_cast<std::uint16_t>(20 + udp_len));
  b.u16(ip_id);
  b.u16(0x4000);  // don't fragment
  b.u8(64);       // TTL
  b.u8(17);       // UDP
  b.u16(0);       // header checksum, below
  b.u32(src_ip);
  b.u32(dst_ip);
  b.patch_u16(ip_at + 10, fold(sum16(std::span(f).subspan(ip_at, 20), 0)));
  const std::size_t udp_at = b.pos();
  b.u16(src_port);
  b.u16(dst_port);
  b.u16(udp_len);
  b.u16(0);
  b.bytes(payload);
  // UDP checksum over the pseudo header (src, dst, protocol, UDP length).
  std::uint32_t acc =
      (src_ip >> 16) + (src_ip & 0xFFFF) + (dst_ip >> 16) + (dst_ip & 0xFFFF) + 17 + udp_len;
  std::uint16_t c = fold(sum16(std::span(f).subspan(udp_at), acc));
  if (c == 0) c = 0xFFFF;
  b.patch_u16(udp_at + 6, c);
  if (f.size() < 60) f.resize(60, 0);
  return f;
}

}  // namespace plc::profinet

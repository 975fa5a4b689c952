#include "plc/profinet/wire/dcp.hpp"

#include <algorithm>
#include <cctype>

namespace plc::profinet {

namespace {

std::vector<std::uint8_t> text_bytes(std::string_view s) { return {s.begin(), s.end()}; }

std::vector<std::uint8_t> ip_suite_bytes(const DcpIpSuite& ip) {
  std::vector<std::uint8_t> d;
  ByteBuilder b(d);
  b.u32(ip.ip);
  b.u32(ip.netmask);
  b.u32(ip.gateway);
  return d;
}

// The identity's value for one (option, suboption); false if we have none.
bool identity_block(const DcpIdentity& id, std::uint8_t opt, std::uint8_t sub, DcpBlock& out) {
  out = DcpBlock{opt, sub, std::uint16_t{0}, {}};
  ByteBuilder b(out.data);
  if (opt == dcp::kOptDevice && sub == dcp::kSubDeviceVendor) {
    out.data = text_bytes(id.type_of_station);
  } else if (opt == dcp::kOptDevice && sub == dcp::kSubDeviceNameOfStation) {
    out.data = text_bytes(id.station_name);
  } else if (opt == dcp::kOptDevice && sub == dcp::kSubDeviceId) {
    b.u16(id.vendor_id);
    b.u16(id.device_id);
  } else if (opt == dcp::kOptDevice && sub == dcp::kSubDeviceRole) {
    b.u8(id.device_role);
    b.u8(0);
  } else if (opt == dcp::kOptDevice && sub == dcp::kSubDeviceOptions) {
    // The (option, suboption) pairs this device answers to.
    const std::uint8_t pairs[][2] = {{dcp::kOptIp, dcp::kSubIpMac},
                                     {dcp::kOptIp, dcp::kSubIpParameter},
                                     {dcp::kOptDevice, dcp::kSubDeviceVendor},
                                     {dcp::kOptDevice, dcp::kSubDeviceNameOfStation},
                                     {dcp::kOptDevice, dcp::kSubDeviceId},
                                     {dcp::kOptDevice, dcp::kSubDeviceRole},
                                     {dcp::kOptDevice, dcp::kSubDeviceOptions},
                                     {dcp::kOptControl, dcp::kSubControlStart},
                                     {dcp::kOptControl, dcp::kSubControlStop},
                                     {dcp::kOptControl, dcp::kSubControlSignal},
                                     {dcp::kOptControl, dcp::kSubControlResponse}};
    for (const auto& p : pairs) {
      b.u8(p[0]);
      b.u8(p[1]);
    }
  } else if (opt == dcp::kOptDevice && sub == dcp::kSubDeviceInstance && id.device_instance) {
    b.u16(*id.device_instance);
  } else if (opt == dcp::kOptIp && sub == dcp::kSubIpParameter) {
    out.info = id.ip_info;
    out.data = ip_suite_bytes(id.ip);
  } else {
    return false;
  }
  return true;
}

// The blocks an Identify response / Hello carries.
std::vector<DcpBlock> identity_blocks(const DcpIdentity& id) {
  std::vector<DcpBlock> blocks;
  const std::uint8_t order[][2] = {
      {dcp::kOptDevice, dcp::kSubDeviceVendor},  {dcp::kOptDevice, dcp::kSubDeviceNameOfStation},
      {dcp::kOptDevice, dcp::kSubDeviceId},      {dcp::kOptDevice, dcp::kSubDeviceRole},
      {dcp::kOptDevice, dcp::kSubDeviceOptions}, {dcp::kOptDevice, dcp::kSubDeviceInstance},
      {dcp::kOptIp, dcp::kSubIpParameter}};
  for (const auto& o : order) {
    DcpBlock b;
    if (identity_block(id, o[0], o[1], b)) blocks.push_back(std::move(b));
  }
  return blocks;
}

std::vector<std::uint8_t> dcp_frame(const Mac& dst, const Mac& src, const DcpMessage& m) {
  const auto pdu = encode_dcp(m);
  return build_pn_frame(dst, src, m.frame_id, pdu);
}

std::string block_text(const DcpBlock& b) { return {b.data.begin(), b.data.end()}; }

}  // namespace

const DcpBlock* DcpMessage::find(std::uint8_t option, std::uint8_t suboption) const {
  for (const auto& b : blocks)
    if (b.option == option && b.suboption == suboption) return &b;
  return nullptr;
}

bool valid_station_name(std::string_view name) {
  // IEC 61158-6-10 NameOfStation: 1..240 octets, labels of 1..63 octets
  // separated by '.', each of [a-z0-9-], not starting or ending with '-';
  // not of the form "n.n.n.n" and not starting with "port-xyz".
  if (name.empty() || name.size() > 240) return false;
  std::size_t label = 0;
  char prev = '.';
  bool all_digits_or_dots = true;
  for (char c : name) {
    if (c == '.') {
      if (label == 0 || prev == '-') return false;
      label = 0;
    } else {
      const bool ok = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-';
      if (!ok) return false;
      if (c == '-' && label == 0) return false;
      if (++label > 63) return false;
      if (!(c >= '0' && c <= '9')) all_digits_or_dots = false;
    }
    prev = c;
  }
  if (label == 0 || prev == '-') return false;
  if (all_digits_or_dots && std::count(name.begin(), name.end(), '.') == 3) return false;
  if (name.rfind("port-", 0) == 0 && name.size() >= 8 &&
      std::isdigit(static_cast<unsigned char>(name[5])) &&
      std::isdigit(static_cast<unsigned char>(name[6])) &&
      std::isdigit(static_cast<unsigned char>(name[7])))
    return false;
  return true;
}

WireStatus decode_dcp(std::uint16_t frame_id, std::span<const std::uint8_t> pdu, DcpMessage& out) {
  if (!is_dcp(frame_id)) return wire_fail(WireError::BadFrameId, "not a DCP FrameID");
  ByteReader r(pdu);
  out = DcpMessage{};
  out.frame_id = frame_id;
  out.service_id = r.u8();
  out.service_type = r.u8();
  out.xid = r.u32();
  out.response_delay = r.u16();
  const std::uint16_t data_length = r.u16();
  if (r.failed()) return wire_fail(WireError::Truncated, "DCP header truncated");
  if (out.service_id < dcp::kServiceGet || out.service_id > dcp::kServiceHello)
    return wire_fail(WireError::BadHeader, "unknown DCP ServiceID");
  if (out.service_type != dcp::kTypeRequest && out.service_type != dcp::kTypeResponseSuccess &&
      out.service_type != dcp::kTypeResponseUnsupported)
    return wire_fail(WireError::BadHeader, "unknown DCP ServiceType");
  const auto data = r.bytes(data_length);  // frame padding after it is ignored
  if (r.failed()) return wire_fail(WireError::BadLength, "DCPDataLength beyond the frame");
  const bool response = out.service_type != dcp::kTypeRequest;
  ByteReader br(data);
  if (out.service_id == dcp::kServiceGet && !response) {
    // A Get request lists (Option, Suboption) pairs without lengths.
    if (data.size() % 2 != 0) return wire_fail(WireError::BadLength, "odd Get request length");
    while (br.remaining() > 0) {
      DcpBlock b;
      b.option = br.u8();
      b.suboption = br.u8();
      out.blocks.push_back(std::move(b));
    }
    return kWireOk;
  }
  const bool with_info =
      response || out.service_id == dcp::kServiceHello || (out.service_id == dcp::kServiceSet);
  while (br.remaining() > 0) {
    DcpBlock b;
    b.option = br.u8();
    b.suboption = br.u8();
    std::uint16_t len = br.u16();
    if (br.failed()) return wire_fail(WireError::Truncated, "DCP block header truncated");
    // Control/Response and the request-side "all selector"/Get lists carry
    // no BlockInfo/Qualifier; Identify requests carry none either.
    const bool control_response =
        b.option == dcp::kOptControl && b.suboption == dcp::kSubControlResponse;
    const bool has_info = with_info && !control_response;
    if (has_info) {
      if (len < 2) return wire_fail(WireError::BadLength, "DCP block shorter than its BlockInfo");
      b.info = br.u16();
      len = static_cast<std::uint16_t>(len - 2);
    }
    const auto v = br.bytes(len);
    if (br.failed()) return wire_fail(WireError::BadLength, "DCP block overruns DCPDataLength");
    b.data.assign(v.begin(), v.end());
    const std::size_t total = (has_info ? 2u : 0u) + len;
    if (total % 2 != 0 && br.remaining() > 0) br.skip(1);  // pad to even
    out.blocks.push_back(std::move(b));
  }
  return kWireOk;
}

std::vector<std::uint8_t> encode_dcp(const DcpMessage& m) {
  std::vector<std::uint8_t> out;
  ByteBuilder b(out);
  b.u8(m.service_id);
  b.u8(m.service_type);
  b.u32(m.xid);
  b.u16(m.response_delay);
  const std::size_t len_at = b.pos();
  b.u16(0);
  const std::size_t start = b.pos();
  for (const auto& blk : m.blocks) {
    b.u8(blk.option);
    b.u8(blk.suboption);
    if (m.service_id == dcp::kServiceGet && m.service_type == dcp::kTypeRequest) continue;
    const std::size_t len = blk.data.size() + (blk.info ? 2 : 0);
    b.u16(static_cast<std::uint16_t>(len));
    if (blk.info) b.u16(*blk.info);
    b.bytes(blk.data);
    // A block of odd DCPBlockLength is followed by one padding octet (IEC
    // 61158-6-10 DCP; not counted in DCPBlockLength). The last block of a
    // request gets it too and DCPDataLength counts it, as p-net's pf_dcp.c
    // and profinet-py send it: Wireshark's packet-pn-dcp.c reads the octet
    // whenever the frame goes on (a 60-byte Ethernet frame always does) and
    // reports "parse error" when DCPDataLength leaves it out.
    if (len % 2 != 0) b.u8(0);
  }
  b.patch_u16(len_at, static_cast<std::uint16_t>(b.pos() - start));
  return out;
}

WireStatus identity_from(const DcpMessage& m, DcpIdentity& out) {
  out = DcpIdentity{};
  if (const auto* b = m.find(dcp::kOptDevice, dcp::kSubDeviceNameOfStation)) {
    out.station_name = block_text(*b);
    if (!out.station_name.empty() && !valid_station_name(out.station_name))
      return wire_fail(WireError::BadValue, "invalid NameOfStation");
  }
  if (const auto* b = m.find(dcp::kOptDevice, dcp::kSubDeviceVendor))
    out.type_of_station = block_text(*b);
  if (const auto* b = m.find(dcp::kOptDevice, dcp::kSubDeviceId)) {
    if (b->data.size() != 4) return wire_fail(WireError::BadLength, "DeviceID block not 4 bytes");
    ByteReader r(b->data);
    out.vendor_id = r.u16();
    out.device_id = r.u16();
  }
  if (const auto* b = m.find(dcp::kOptDevice, dcp::kSubDeviceRole)) {
    if (b->data.size() != 2) return wire_fail(WireError::BadLength, "DeviceRole block not 2 bytes");
    out.device_role = b->data[0];
  }
  if (const auto* b = m.find(dcp::kOptDevice, dcp::kSubDeviceInstance)) {
    if (b->data.size() != 2) return wire_fail(WireError::BadLength, "DeviceInstance not 2 bytes");
    ByteReader r(b->data);
    out.device_instance = r.u16();
  }
  if (const auto* b = m.find(dcp::kOptIp, dcp::kSubIpParameter)) {
    if (b->data.size() != 12) return wire_fail(WireError::BadLength, "IP parameter not 12 bytes");
    ByteReader r(b->data);
    out.ip.ip = r.u32();
    out.ip.netmask = r.u32();
    out.ip.gateway = r.u32();
    out.ip_info = b->info.value_or(0);
  }
  return kWireOk;
}

WireStatus set_request_from(const DcpMessage& m, DcpSetRequest& out) {
  out = DcpSetRequest{};
  if (m.service_id != dcp::kServiceSet || m.service_type != dcp::kTypeRequest)
    return wire_fail(WireError::BadHeader, "not a DCP Set request");
  bool any_qualifier = false;
  out.permanent = false;
  for (const auto& b : m.blocks) {
    if (b.info && (*b.info & dcp::kQualifierPermanent)) out.permanent = true;
    any_qualifier = any_qualifier || b.info.has_value();
    if (b.option == dcp::kOptDevice && b.suboption == dcp::kSubDeviceNameOfStation) {
      out.station_name = block_text(b);
      if (!out.station_name->empty() && !valid_station_name(*out.station_name))
        return wire_fail(WireError::BadValue, "invalid NameOfStation");
    } else if (b.option == dcp::kOptIp && b.suboption == dcp::kSubIpParameter) {
      if (b.data.size() != 12) return wire_fail(WireError::BadLength, "IP parameter not 12 bytes");
      ByteReader r(b.data);
      out.ip = DcpIpSuite{r.u32(), r.u32(), r.u32()};
    } else if (b.option == dcp::kOptControl && b.suboption == dcp::kSubControlSignal) {
      out.signal = true;
    } else if (b.option == dcp::kOptControl && b.suboption == dcp::kSubControlResetToFactory) {
      out.reset_factory = true;
    }
  }
  (void)any_qualifier;
  return kWireOk;
}

WireStatus set_results_from(const DcpMessage& m, std::vector<DcpSetResult>& out) {
  out.clear();
  for (const auto& b : m.blocks) {
    if (b.option != dcp::kOptControl || b.suboption != dcp::kSubControlResponse) continue;
    if (b.data.size() != 3) return wire_fail(WireError::BadLength, "Control/Response not 3 bytes");
    out.push_back({b.data[0], b.data[1], b.data[2]});
  }
  return kWireOk;
}

std::optional<std::string> identify_filter(const DcpMessage& m) {
  if (const auto* b = m.find(dcp::kOptDevice, dcp::kSubDeviceNameOfStation)) return block_text(*b);
  return std::nullopt;
}

std::vector<std::uint8_t> encode_dcp_identify_request(const Mac& src, std::uint32_t xid,
                                                      std::optional<std::string_view> name,
                                                      std::uint16_t response_delay) {
  DcpMessage m{frame_id::kDcpIdentifyRequest,
               dcp::kServiceIdentify,
               dcp::kTypeRequest,
               xid,
               response_delay,
               {}};
  if (name)
    m.blocks.push_back({dcp::kOptDevice, dcp::kSubDeviceNameOfStation, {}, text_bytes(*name)});
  else
    m.blocks.push_back({dcp::kOptAll, dcp::kSubAll, {}, {}});
  return dcp_frame(kDcpIdentifyMulticast, src, m);
}

std::vector<std::uint8_t> encode_dcp_identify_response(const Mac& dst, const Mac& src,
                                                       std::uint32_t xid, const DcpIdentity& id) {
  DcpMessage m{frame_id::kDcpIdentifyResponse,
               dcp::kServiceIdentify,
               dcp::kTypeResponseSuccess,
               xid,
               0,
               identity_blocks(id)};
  return dcp_frame(dst, src, m);
}

std::vector<std::uint8_t> encode_dcp_hello(const Mac& src, std::uint32_t xid,
                                           const DcpIdentity& id) {
  DcpMessage m{frame_id::kDcpHello, dcp::kServiceHello, dcp::kTypeRequest, xid, 0,
               identity_blocks(id)};
  return dcp_frame(kDcpHelloMulticast, src, m);
}

std::vector<std::uint8_t> encode_dcp_set_request(const Mac& dst, const Mac& src, std::uint32_t xid,
                                                 const DcpSetRequest& req) {
  const std::uint16_t q = req.permanent ? dcp::kQualifierPermanent : dcp::kQualifierTemporary;
  DcpMessage m{frame_id::kDcpGetSet, dcp::kServiceSet, dcp::kTypeRequest, xid, 0, {}};
  if (req.station_name)
    m.blocks.push_back(
        {dcp::kOptDevice, dcp::kSubDeviceNameOfStation, q, text_bytes(*req.station_name)});
  if (req.ip) m.blocks.push_back({dcp::kOptIp, dcp::kSubIpParameter, q, ip_suite_bytes(*req.ip)});
  if (req.signal) m.blocks.push_back({dcp::kOptControl, dcp::kSubControlSignal, 0, {0x01, 0x00}});
  if (req.reset_factory)
    m.blocks.push_back({dcp::kOptControl, dcp::kSubControlResetToFactory, 0x0004, {}});
  return dcp_frame(dst, src, m);
}

std::vector<std::uint8_t> encode_dcp_set_response(const Mac& dst, const Mac& src, std::uint32_t xid,
                                                  std::span<const DcpSetResult> results) {
  DcpMessage m{frame_id::kDcpGetSet, dcp::kServiceSet, dcp::kTypeResponseSuccess, xid, 0, {}};
  for (const auto& r : results)
    m.blocks.push_back(
        {dcp::kOptControl, dcp::kSubControlResponse, {}, {r.option, r.suboption, r.error}});
  return dcp_frame(dst, src, m);
}

std::vector<std::uint8_t> encode_dcp_get_request(
    const Mac& dst, const Mac& src, std::uint32_t xid,
    std::span<const std::pair<std::uint8_t, std::uint8_t>> options) {
  DcpMessage m{frame_id::kDcpGetSet, dcp::kServiceGet, dcp::kTypeRequest, xid, 0, {}};
  // A Get request lists the wanted (option, suboption) pairs.
  for (const auto& [o, s] : options) m.blocks.push_back({o, s, {}, {}});
  return dcp_frame(dst, src, m);
}

std::vector<std::uint8_t> encode_dcp_get_response(
    const Mac& dst, const Mac& src, std::uint32_t xid, const DcpIdentity& id,
    std::span<const std::pair<std::uint8_t, std::uint8_t>> options) {
  DcpMessage m{frame_id::kDcpGetSet, dcp::kServiceGet, dcp::kTypeResponseSuccess, xid, 0, {}};
  for (const auto& [o, s] : options) {
    DcpBlock b;
    if (identity_block(id, o, s, b))
      m.blocks.push_back(std::move(b));
    else
      m.blocks.push_back({dcp::kOptControl,
                          dcp::kSubControlResponse,
                          {},
                          {o, s, dcp::kErrorSuboptionUnsupported}});
  }
  return dcp_frame(dst, src, m);
}

}  // namespace plc::profinet

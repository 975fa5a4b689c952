// The IO blocks of IEC 61158-6-10 §5.2 (field order and padding as in the
// standard's "Coding of the fields" and checked against Wireshark's
// packet-dcerpc-pn-io.c dissector by tests/profinet/test_wire_tshark.cpp).
#include "plc/profinet/wire/blocks.hpp"

#include <algorithm>

namespace plc::profinet {

namespace {

WireStatus need_type(const BlockView& v, std::uint16_t type) {
  if (v.type != type) return wire_fail(WireError::BadBlockType, "unexpected block type");
  if (v.version_high != 1 || v.version_low != 0)
    return wire_fail(WireError::BadBlockVersion, "block version not 1.0");
  return kWireOk;
}

WireStatus finish(const ByteReader& r, const char* what) {
  if (r.failed()) return wire_fail(WireError::Truncated, what);
  return kWireOk;
}

void put_mac(ByteBuilder& b, const Mac& m) { b.bytes(m); }
Mac get_mac(ByteReader& r) {
  Mac m{};
  const auto d = r.bytes(6);
  if (d.size() == 6) std::copy(d.begin(), d.end(), m.begin());
  return m;
}
std::string get_text(ByteReader& r, std::size_t n) {
  const auto d = r.bytes(n);
  return {d.begin(), d.end()};
}
}  // namespace

WireStatus read_block(ByteReader& r, BlockView& out) {
  out.type = r.u16();
  out.length = r.u16();
  if (r.failed()) return wire_fail(WireError::Truncated, "block header truncated");
  if (out.length < 2) return wire_fail(WireError::BadLength, "BlockLength below 2");
  if (out.length > r.remaining())
    return wire_fail(WireError::BadLength, "BlockLength beyond the data");
  out.version_high = r.u8();
  out.version_low = r.u8();
  out.body = r.bytes(out.length - 2u);
  return kWireOk;
}

std::size_t begin_block(ByteBuilder& b, std::uint16_t type, std::uint8_t version_low) {
  const std::size_t start = b.pos();
  b.u16(type);
  b.u16(0);
  b.u8(1);
  b.u8(version_low);
  return start;
}

void end_block(ByteBuilder& b, std::size_t start) {
  b.patch_u16(start + 2, static_cast<std::uint16_t>(b.pos() - start - 4));
}

// --- ARBlock -----------------------------------------------------------------

void encode_block(ByteBuilder& b, const ArBlockReq& v) {
  const auto s = begin_block(b, block::kArBlockReq);
  b.u16(v.ar_type);
  put_uuid(b, v.ar_uuid);
  b.u16(v.session_key);
  put_mac(b, v.cm_initiator_mac);
  put_uuid(b, v.cm_initiator_object_uuid);
  b.u32(v.ar_properties);
  b.u16(v.activity_timeout_factor);
  b.u16(v.initiator_udp_rt_port);
  b.u16(static_cast<std::uint16_t>(v.station_name.size()));
  b.bytes({reinterpret_cast<const std::uint8_t*>(v.station_name.data()), v.station_name.size()});
  end_block(b, s);
}

WireStatus decode_block(const BlockView& v, ArBlockReq& out) {
  if (auto st = need_type(v, block::kArBlockReq); !st) return st;
  ByteReader r(v.body);
  out.ar_type = r.u16();
  out.ar_uuid = get_uuid(r);
  out.session_key = r.u16();
  out.cm_initiator_mac = get_mac(r);
  out.cm_initiator_object_uuid = get_uuid(r);
  out.ar_properties = r.u32();
  out.activity_timeout_factor = r.u16();
  out.initiator_udp_rt_port = r.u16();
  const std::uint16_t n = r.u16();
  if (!r.failed() && n > 240) return wire_fail(WireError::BadValue, "station name above 240 bytes");
  out.station_name = get_text(r, n);
  if (r.failed()) return wire_fail(WireError::Truncated, "ARBlockReq truncated");
  if (r.remaining() != 0)
    return wire_fail(WireError::BadLength, "ARBlockReq longer than its fields");
  return kWireOk;
}

void encode_block(ByteBuilder& b, const ArBlockRes& v) {
  const auto s = begin_block(b, block::kArBlockRes);
  b.u16(v.ar_type);
  put_uuid(b, v.ar_uuid);
  b.u16(v.session_key);
  put_mac(b, v.cm_responder_mac);
  b.u16(v.responder_udp_rt_port);
  end_block(b, s);
}

WireStatus decode_block(const BlockView& v, ArBlockRes& out) {
  if (auto st = need_type(v, block::kArBlockRes); !st) return st;
  ByteReader r(v.body);
  out.ar_type = r.u16();
  out.ar_uuid = get_uuid(r);
  out.session_key = r.u16();
  out.cm_responder_mac = get_mac(r);
  out.responder_udp_rt_port = r.u16();
  return finish(r, "ARBlockRes truncated");
}

// --- IOCRBlock -----------------------------------------------------------------

void encode_block(ByteBuilder& b, const IocrBlockReq& v) {
  const auto s = begin_block(b, block::kIocrBlockReq);
  b.u16(v.iocr_type);
  b.u16(v.iocr_reference);
  b.u16(v.lt);
  b.u32(v.iocr_properties);
  b.u16(v.data_length);
  b.u16(v.frame_id);
  b.u16(v.send_clock_factor);
  b.u16(v.reduction_ratio);
  b.u16(v.phase);
  b.u16(v.sequence);
  b.u32(v.frame_send_offset);
  b.u16(v.watchdog_factor);
  b.u16(v.data_hold_factor);
  b.u16(v.iocr_tag_header);
  put_mac(b, v.multicast_mac);
  b.u16(static_cast<std::uint16_t>(v.apis.size()));
  for (const auto& api : v.apis) {
    b.u32(api.api);
    b.u16(static_cast<std::uint16_t>(api.data_objects.size()));
    for (const auto& e : api.data_objects) {
      b.u16(e.slot);
      b.u16(e.subslot);
      b.u16(e.frame_offset);
    }
    b.u16(static_cast<std::uint16_t>(api.iocs.size()));
    for (const auto& e : api.iocs) {
      b.u16(e.slot);
      b.u16(e.subslot);
      b.u16(e.frame_offset);
    }
  }
  end_block(b, s);
}

WireStatus decode_block(const BlockView& v, IocrBlockReq& out) {
  if (auto st = need_type(v, block::kIocrBlockReq); !st) return st;
  ByteReader r(v.body);
  out.iocr_type = r.u16();
  out.iocr_reference = r.u16();
  out.lt = r.u16();
  out.iocr_properties = r.u32();
  out.data_length = r.u16();
  out.frame_id = r.u16();
  out.send_clock_factor = r.u16();
  out.reduction_ratio = r.u16();
  out.phase = r.u16();
  out.sequence = r.u16();
  out.frame_send_offset = r.u32();
  out.watchdog_factor = r.u16();
  out.data_hold_factor = r.u16();
  out.iocr_tag_header = r.u16();
  out.multicast_mac = get_mac(r);
  const std::uint16_t apis = r.u16();
  out.apis.clear();
  // Each API entry needs at least 8 bytes: bounds the loop by the data.
  for (std::uint16_t i = 0; i < apis && !r.failed(); ++i) {
    IocrApi a;
    a.api = r.u32();
    const std::uint16_t n = r.u16();
    if (std::size_t{n} * 6 > r.remaining())
      return wire_fail(WireError::BadLength, "IOCR data objects overrun the block");
    for (std::uint16_t k = 0; k < n; ++k) a.data_objects.push_back({r.u16(), r.u16(), r.u16()});
    const std::uint16_t m = r.u16();
    if (std::size_t{m} * 6 > r.remaining())
      return wire_fail(WireError::BadLength, "IOCR IOCS entries overrun the block");
    for (std::uint16_t k = 0; k < m; ++k) a.iocs.push_back({r.u16(), r.u16(), r.u16()});
    out.apis.push_back(std::move(a));
  }
  if (r.failed()) return wire_fail(WireError::Truncated, "IOCRBlockReq truncated");
  if (r.remaining() != 0)
    return wire_fail(WireError::BadLength, "IOCRBlockReq longer than its fields");
  return kWireOk;
}

void encode_block(ByteBuilder& b, const IocrBlockRes& v) {
  const auto s = begin_block(b, block::kIocrBlockRes);
  b.u16(v.iocr_type);
  b.u16(v.iocr_reference);
  b.u16(v.frame_id);
  end_block(b, s);
}

WireStatus decode_block(const BlockView& v, IocrBlockRes& out) {
  if (auto st = need_type(v, block::kIocrBlockRes); !st) return st;
  ByteReader r(v.body);
  out.iocr_type = r.u16();
  out.iocr_reference = r.u16();
  out.frame_id = r.u16();
  return finish(r, "IOCRBlockRes truncated");
}

// --- AlarmCRBlock --------------------------------------------------------------

void encode_block(ByteBuilder& b, const AlarmCrBlockReq& v) {
  const auto s = begin_block(b, block::kAlarmCrBlockReq);
  b.u16(v.alarm_cr_type);
  b.u16(v.lt);
  b.u32(v.properties);
  b.u16(v.rta_timeout_factor);
  b.u16(v.rta_retries);
  b.u16(v.local_alarm_reference);
  b.u16(v.max_alarm_data_length);
  b.u16(v.tag_header_high);
  b.u16(v.tag_header_low);
  end_block(b, s);
}

WireStatus decode_block(const BlockView& v, AlarmCrBlockReq& out) {
  if (auto st = need_type(v, block::kAlarmCrBlockReq); !st) return st;
  ByteReader r(v.body);
  out.alarm_cr_type = r.u16();
  out.lt = r.u16();
  out.properties = r.u32();
  out.rta_timeout_factor = r.u16();
  out.rta_retries = r.u16();
  out.local_alarm_reference = r.u16();
  out.max_alarm_data_length = r.u16();
  out.tag_header_high = r.u16();
  out.tag_header_low = r.u16();
  if (r.failed()) return wire_fail(WireError::Truncated, "AlarmCRBlockReq truncated");
  if (r.remaining() != 0)
    return wire_fail(WireError::BadLength, "AlarmCRBlockReq longer than its fields");
  return kWireOk;
}

void encode_block(ByteBuilder& b, const AlarmCrBlockRes& v) {
  const auto s = begin_block(b, block::kAlarmCrBlockRes);
  b.u16(v.alarm_cr_type);
  b.u16(v.local_alarm_reference);
  b.u16(v.max_alarm_data_length);
  end_block(b, s);
}

WireStatus decode_block(const BlockView& v, AlarmCrBlockRes& out) {
  if (auto st = need_type(v, block::kAlarmCrBlockRes); !st) return st;
  ByteReader r(v.body);
  out.alarm_cr_type = r.u16();
  out.local_alarm_reference = r.u16();
  out.max_alarm_data_length = r.u16();
  return finish(r, "AlarmCRBlockRes truncated");
}

// --- ExpectedSubmoduleBlockReq ----------------------------------------------------

std::uint16_t ExpectedSubmodule::type() const {
  if (wire_type) return *wire_type;
  if (input_length > 0 && output_length > 0) return submodule::kTypeInputOutput;
  if (output_length > 0) return submodule::kTypeOutput;
  if (input_length > 0) return submodule::kTypeInput;
  return submodule::kTypeNoIo;
}

std::vector<DataDescription> ExpectedSubmodule::wire_descriptions() const {
  if (!descriptions.empty()) return descriptions;
  // Input first (NO_IO: one input description of length 0), then output.
  std::vector<DataDescription> d;
  const std::uint16_t t = type();
  if (t != submodule::kTypeOutput)
    d.push_back({submodule::kDataInput, input_length, length_iocs, length_iops});
  if (t == submodule::kTypeOutput || t == submodule::kTypeInputOutput)
    d.push_back({submodule::kDataOutput, output_length, length_iocs, length_iops});
  return d;
}

const DataDescription* ExpectedSubmodule::description(std::uint16_t direction) const {
  for (const auto& d : descriptions)
    if (d.direction == direction) return &d;
  return nullptr;
}

void encode_block(ByteBuilder& b, const ExpectedSubmoduleBlockReq& v) {
  const auto s = begin_block(b, block::kExpectedSubmoduleBlockReq);
  b.u16(static_cast<std::uint16_t>(v.modules.size()));  // NumberOfAPIs: one entry per module
  for (const auto& m : v.modules) {
    b.u32(m.api);
    b.u16(m.slot);
    b.u32(m.module_ident);
    b.u16(m.module_properties);
    b.u16(static_cast<std::uint16_t>(m.submodules.size()));
    for (const auto& sm : m.submodules) {
      b.u16(sm.subslot);
      b.u32(sm.submodule_ident);
      b.u16(static_cast<std::uint16_t>((sm.properties & ~0x0003u) | (sm.type() & 0x0003u)));
      for (const auto& d : sm.wire_descriptions()) {
        b.u16(d.direction);
        b.u16(d.length);
        b.u8(d.length_iocs);
        b.u8(d.length_iops);
      }
    }
  }
  end_block(b, s);
}

// Reads what is there and keeps it (wire_type, descriptions): the values
// are the device's to check (connect_check.hpp), with p-net's codes. The
// number of DataDescriptions follows from the Type: two for an IO
// submodule, else one.
WireStatus decode_block(const BlockView& v, ExpectedSubmoduleBlockReq& out) {
  if (auto st = need_type(v, block::kExpectedSubmoduleBlockReq); !st) return st;
  ByteReader r(v.body);
  out.modules.clear();
  const std::uint16_t n = r.u16();
  for (std::uint16_t i = 0; i < n && !r.failed(); ++i) {
    ExpectedModule m;
    m.api = r.u32();
    m.slot = r.u16();
    m.module_ident = r.u32();
    m.module_properties = r.u16();
    const std::uint16_t subs = r.u16();
    for (std::uint16_t k = 0; k < subs && !r.failed(); ++k) {
      ExpectedSubmodule sm;
      sm.subslot = r.u16();
      sm.submodule_ident = r.u32();
      const std::uint16_t props = r.u16();
      sm.wire_type = props & 0x0003;
      sm.properties = props & ~std::uint16_t{0x0003};
      const int count = *sm.wire_type == submodule::kTypeInputOutput ? 2 : 1;
      for (int d = 0; d < count && !r.failed(); ++d) {
        DataDescription dd;
        dd.direction = r.u16();
        dd.length = r.u16();
        dd.length_iocs = r.u8();
        dd.length_iops = r.u8();
        sm.descriptions.push_back(dd);
      }
      if (const auto* in = sm.description(submodule::kDataInput)) sm.input_length = in->length;
      if (const auto* o = sm.description(submodule::kDataOutput)) sm.output_length = o->length;
      if (!sm.descriptions.empty()) {
        sm.length_iocs = sm.descriptions.front().length_iocs;
        sm.length_iops = sm.descriptions.front().length_iops;
      }
      m.submodules.push_back(std::move(sm));
    }
    out.modules.push_back(std::move(m));
  }
  if (r.failed()) return wire_fail(WireError::Truncated, "ExpectedSubmoduleBlockReq truncated");
  if (r.remaining() != 0)
    return wire_fail(WireError::BadLength, "ExpectedSubmoduleBlockReq longer than its fields");
  return kWireOk;
}

// --- ARRPCBlockReq ------------------------------------------------------------------

void encode_block(ByteBuilder& b, const ArRpcBlockReq& v) {
  const auto s = begin_block(b, block::kArRpcBlockReq);
  b.u16(v.initiator_rpc_server_port);
  end_block(b, s);
}

WireStatus decode_block(const BlockView& v, ArRpcBlockReq& out) {
  if (auto st = need_type(v, block::kArRpcBlockReq); !st) return st;
  ByteReader r(v.body);
  out.initiator_rpc_server_port = r.u16();
  if (r.failed()) return wire_fail(WireError::Truncated, "ARRPCBlockReq truncated");
  if (r.remaining() != 0)
    return wire_fail(WireError::BadLength, "ARRPCBlockReq longer than its fields");
  return kWireOk;
}

// --- ModuleDiffBlock, ARServerBlock ------------------------------------------------

void encode_block(ByteBuilder& b, const ModuleDiffBlock& v) {
  const auto s = begin_block(b, block::kModuleDiffBlock);
  b.u16(static_cast<std::uint16_t>(v.apis.size()));
  for (const auto& a : v.apis) {
    b.u32(a.api);
    b.u16(static_cast<std::uint16_t>(a.modules.size()));
    for (const auto& m : a.modules) {
      b.u16(m.slot);
      b.u32(m.module_ident);
      b.u16(m.state);
      b.u16(static_cast<std::uint16_t>(m.submodules.size()));
      for (const auto& sm : m.submodules) {
        b.u16(sm.subslot);
        b.u32(sm.submodule_ident);
        b.u16(sm.state);
      }
    }
  }
  end_block(b, s);
}

WireStatus decode_block(const BlockView& v, ModuleDiffBlock& out) {
  if (auto st = need_type(v, block::kModuleDiffBlock); !st) return st;
  ByteReader r(v.body);
  out.apis.clear();
  const std::uint16_t n = r.u16();
  for (std::uint16_t i = 0; i < n && !r.failed(); ++i) {
    ModuleDiffApi a;
    a.api = r.u32();
    const std::uint16_t mods = r.u16();
    for (std::uint16_t k = 0; k < mods && !r.failed(); ++k) {
      ModuleDiffModule m;
      m.slot = r.u16();
      m.module_ident = r.u32();
      m.state = r.u16();
      const std::uint16_t subs = r.u16();
      if (std::size_t{subs} * 8 > r.remaining())
        return wire_fail(WireError::BadLength, "ModuleDiffBlock submodules overrun");
      for (std::uint16_t j = 0; j < subs; ++j) m.submodules.push_back({r.u16(), r.u32(), r.u16()});
      a.modules.push_back(std::move(m));
    }
    out.apis.push_back(std::move(a));
  }
  return finish(r, "ModuleDiffBlock truncated");
}

void encode_block(ByteBuilder& b, const ArServerBlock& v) {
  const auto s = begin_block(b, block::kArServerBlock);
  b.u16(static_cast<std::uint16_t>(v.station_name.size()));
  b.bytes({reinterpret_cast<const std::uint8_t*>(v.station_name.data()), v.station_name.size()});
  b.align(4, s);  // padding: the block is a multiple of 4 bytes
  end_block(b, s);
}

WireStatus decode_block(const BlockView& v, ArServerBlock& out) {
  if (auto st = need_type(v, block::kArServerBlock); !st) return st;
  ByteReader r(v.body);
  const std::uint16_t n = r.u16();
  out.station_name = get_text(r, n);
  return finish(r, "ARServerBlock truncated");
}

// --- Connect ---------------------------------------------------------------------

std::vector<std::uint8_t> encode_connect_request(const ConnectRequest& req) {
  std::vector<std::uint8_t> out;
  ByteBuilder b(out);
  encode_block(b, req.ar);
  for (const auto& c : req.iocrs) encode_block(b, c);
  for (std::uint16_t i = 0; i < req.alarm_cr_blocks; ++i) encode_block(b, req.alarm_cr);
  for (const auto& e : req.expected) encode_block(b, e);
  if (req.ar_rpc) encode_block(b, *req.ar_rpc);
  return out;
}

std::vector<std::uint8_t> encode_connect_response(const ConnectResponse& res) {
  std::vector<std::uint8_t> out;
  ByteBuilder b(out);
  encode_block(b, res.ar);
  for (const auto& c : res.iocrs) encode_block(b, c);
  encode_block(b, res.alarm_cr);
  if (res.module_diff) encode_block(b, *res.module_diff);
  if (res.ar_server) encode_block(b, *res.ar_server);
  return out;
}

WireStatus decode_connect_request(std::span<const std::uint8_t> args, ConnectRequest& out) {
  out = ConnectRequest{};
  out.alarm_cr_blocks = 0;
  ByteReader r(args);
  bool have_ar = false;
  while (r.remaining() > 0) {
    BlockView v;
    if (auto st = read_block(r, v); !st) return st;
    WireStatus st;
    switch (v.type) {
      case block::kArBlockReq:
        if (have_ar) return wire_fail(WireError::BadBlockType, "second ARBlockReq");
        have_ar = true;
        st = decode_block(v, out.ar);
        break;
      case block::kIocrBlockReq:
        if (out.iocrs.size() >= 64) return wire_fail(WireError::BadValue, "too many IOCRBlockReq");
        st = decode_block(v, out.iocrs.emplace_back());
        break;
      case block::kAlarmCrBlockReq:
        if (out.alarm_cr_blocks >= 64)
          return wire_fail(WireError::BadValue, "too many AlarmCRBlockReq");
        ++out.alarm_cr_blocks;
        st = decode_block(v, out.alarm_cr);
        break;
      case block::kExpectedSubmoduleBlockReq:
        st = decode_block(v, out.expected.emplace_back());
        break;
      case block::kArRpcBlockReq:
        st = decode_block(v, out.ar_rpc.emplace());  // a second one replaces the first
        break;
      default:
        // The other optional request blocks (PrmServer, MCR, ARVendor,
        // IRInfo, ...) are refused, as a p-net device built with its
        // default options refuses them.
        return wire_fail(WireError::BadBlockType, "unexpected block in a Connect request");
    }
    if (!st) return st;
  }
  if (!have_ar) return wire_fail(WireError::BadBlockType, "Connect request without ARBlockReq");
  return kWireOk;
}

WireStatus decode_connect_response(std::span<const std::uint8_t> args, ConnectResponse& out) {
  out = ConnectResponse{};
  ByteReader r(args);
  bool have_ar = false, have_alarm = false;
  while (r.remaining() > 0) {
    BlockView v;
    if (auto st = read_block(r, v); !st) return st;
    WireStatus st;
    switch (v.type) {
      case block::kArBlockRes:
        if (have_ar) return wire_fail(WireError::BadBlockType, "second ARBlockRes");
        have_ar = true;
        st = decode_block(v, out.ar);
        break;
      case block::kIocrBlockRes:
        if (out.iocrs.size() >= 64) return wire_fail(WireError::BadValue, "too many IOCRBlockRes");
        st = decode_block(v, out.iocrs.emplace_back());
        break;
      case block::kAlarmCrBlockRes:
        if (have_alarm) return wire_fail(WireError::BadBlockType, "second AlarmCRBlockRes");
        have_alarm = true;
        st = decode_block(v, out.alarm_cr);
        break;
      case block::kModuleDiffBlock:
        st = decode_block(v, out.module_diff.emplace());
        break;
      case block::kArServerBlock:
        st = decode_block(v, out.ar_server.emplace());
        break;
      default:
        break;  // other optional result blocks (ARRPCBlockRes, ...) are skipped
    }
    if (!st) return st;
  }
  if (!have_ar) return wire_fail(WireError::BadBlockType, "Connect response without ARBlockRes");
  if (!have_alarm)
    return wire_fail(WireError::BadBlockType, "Connect response without AlarmCRBlockRes");
  return kWireOk;
}

// --- Record read / write -----------------------------------------------------------

void encode_block(ByteBuilder& b, std::uint16_t type, const RecordRequestHeader& h) {
  const auto s = begin_block(b, type);
  b.u16(h.seq_number);
  put_uuid(b, h.ar_uuid);
  b.u32(h.api);
  b.u16(h.slot);
  b.u16(h.subslot);
  b.zeros(2);  // padding
  b.u16(h.index);
  b.u32(h.record_data_length);
  b.zeros(24);  // RWPadding (read: TargetARUUID nil + 8 bytes, explicit AR)
  end_block(b, s);
}

WireStatus decode_block(const BlockView& v, RecordRequestHeader& out) {
  if (v.type != block::kWriteReqHeader && v.type != block::kReadReqHeader)
    return wire_fail(WireError::BadBlockType, "not an IODWriteReqHeader/IODReadReqHeader");
  if (auto st = need_type(v, v.type); !st) return st;
  if (v.body.size() != 58)
    return wire_fail(WireError::BadLength, "record request header not 60 bytes");
  ByteReader r(v.body);
  out.seq_number = r.u16();
  out.ar_uuid = get_uuid(r);
  out.api = r.u32();
  out.slot = r.u16();
  out.subslot = r.u16();
  r.skip(2);
  out.index = r.u16();
  out.record_data_length = r.u32();
  return finish(r, "record request header truncated");
}

void encode_block(ByteBuilder& b, std::uint16_t type, const RecordResponseHeader& h) {
  const auto s = begin_block(b, type);
  b.u16(h.seq_number);
  put_uuid(b, h.ar_uuid);
  b.u32(h.api);
  b.u16(h.slot);
  b.u16(h.subslot);
  b.zeros(2);
  b.u16(h.index);
  b.u32(h.record_data_length);
  b.u16(h.additional_value1);
  b.u16(h.additional_value2);
  if (type == block::kWriteResHeader) {
    put_pnio_status(b, h.status);
    b.zeros(16);
  } else {
    b.zeros(20);
  }
  end_block(b, s);
}

WireStatus decode_block(const BlockView& v, RecordResponseHeader& out) {
  if (v.type != block::kWriteResHeader && v.type != block::kReadResHeader)
    return wire_fail(WireError::BadBlockType, "not an IODWriteResHeader/IODReadResHeader");
  if (auto st = need_type(v, v.type); !st) return st;
  if (v.body.size() != 58)
    return wire_fail(WireError::BadLength, "record response header not 60 bytes");
  ByteReader r(v.body);
  out.seq_number = r.u16();
  out.ar_uuid = get_uuid(r);
  out.api = r.u32();
  out.slot = r.u16();
  out.subslot = r.u16();
  r.skip(2);
  out.index = r.u16();
  out.record_data_length = r.u32();
  out.additional_value1 = r.u16();
  out.additional_value2 = r.u16();
  out.status = v.type == block::kWriteResHeader ? get_pnio_status(r) : PnioStatus{};
  return finish(r, "record response header truncated");
}

std::vector<std::uint8_t> encode_write_request(std::uint16_t seq, const Uuid& ar_uuid,
                                               std::span<const RecordWrite> records,
                                               bool force_multiple) {
  std::vector<std::uint8_t> out;
  ByteBuilder b(out);
  auto header_of = [&](const RecordWrite& w) {
    return RecordRequestHeader{
        seq, ar_uuid, w.api, w.slot, w.subslot, w.index, static_cast<std::uint32_t>(w.data.size())};
  };
  if (records.size() == 1 && !force_multiple) {
    encode_write_request_to(out, header_of(records[0]), records[0].data);
    return out;
  }
  const std::size_t outer = b.pos();
  encode_block(
      b, block::kWriteReqHeader,
      RecordRequestHeader{seq, ar_uuid, record::kApiMultipleWrite, record::kSlotMultipleWrite,
                          record::kSubslotMultipleWrite, record::kIndexMultipleWrite, 0});
  const std::size_t data_start = b.pos();
  for (std::size_t i = 0; i < records.size(); ++i) {
    if (i > 0) b.align(4, data_start);  // padding between records, not after the last
    encode_block(b, block::kWriteReqHeader, header_of(records[i]));
    b.bytes(records[i].data);
  }
  // RecordDataLength of the outer header: everything after it.
  b.patch_u32(outer + 6 + 2 + 16 + 4 + 2 + 2 + 2 + 2,
              static_cast<std::uint32_t>(b.pos() - data_start));
  return out;
}

WireStatus decode_write_request(std::span<const std::uint8_t> args, WriteRequest& out) {
  out = WriteRequest{};
  ByteReader r(args);
  BlockView v;
  if (auto st = read_block(r, v); !st) return st;
  if (v.type != block::kWriteReqHeader)
    return wire_fail(WireError::BadBlockType, "not an IODWriteReqHeader");
  if (auto st = decode_block(v, out.header); !st) return st;
  if (out.header.record_data_length != r.remaining())
    return wire_fail(WireError::BadLength, "RecordDataLength disagrees with the data");
  const auto data = r.bytes(out.header.record_data_length);
  if (!out.multiple()) {
    out.data = data;
    return kWireOk;
  }
  ByteReader m(data);
  while (m.remaining() > 0) {
    if (!out.sub_headers.empty()) {
      const std::size_t pad = (4 - m.pos() % 4) % 4;
      if (pad > m.remaining())
        return wire_fail(WireError::BadLength, "MultipleWrite padding truncated");
      m.skip(pad);
    }
    BlockView sv;
    if (auto st = read_block(m, sv); !st) return st;
    if (sv.type != block::kWriteReqHeader)
      return wire_fail(WireError::BadBlockType, "not an IODWriteReqHeader in MultipleWrite");
    RecordRequestHeader h;
    if (auto st = decode_block(sv, h); !st) return st;
    if (h.index == record::kIndexMultipleWrite)
      return wire_fail(WireError::BadValue, "nested MultipleWrite");
    const auto d = m.bytes(h.record_data_length);
    if (m.failed()) return wire_fail(WireError::BadLength, "MultipleWrite record data truncated");
    out.sub_headers.push_back(h);
    out.sub_data.push_back(d);
  }
  return kWireOk;
}

void encode_write_request_to(std::vector<std::uint8_t>& out, const RecordRequestHeader& h,
                             std::span<const std::uint8_t> data) {
  out.clear();
  ByteBuilder b(out);
  RecordRequestHeader hh = h;
  hh.record_data_length = static_cast<std::uint32_t>(data.size());
  encode_block(b, block::kWriteReqHeader, hh);
  b.bytes(data);
}

std::vector<std::uint8_t> encode_write_response(const WriteResponse& res) {
  std::vector<std::uint8_t> out;
  encode_write_response_to(out, res);
  return out;
}

void encode_write_response_to(std::vector<std::uint8_t>& out, const WriteResponse& res) {
  out.clear();
  ByteBuilder b(out);
  encode_block(b, block::kWriteResHeader, res.header);
  const std::size_t data_start = b.pos();
  for (std::size_t i = 0; i < res.sub_results.size(); ++i) {
    if (i > 0) b.align(4, data_start);
    encode_block(b, block::kWriteResHeader, res.sub_results[i]);
  }
}

WireStatus decode_write_response(std::span<const std::uint8_t> args, WriteResponse& out) {
  out = WriteResponse{};
  ByteReader r(args);
  BlockView v;
  if (auto st = read_block(r, v); !st) return st;
  if (v.type != block::kWriteResHeader)
    return wire_fail(WireError::BadBlockType, "not an IODWriteResHeader");
  if (auto st = decode_block(v, out.header); !st) return st;
  const std::size_t data_start = r.pos();
  while (r.remaining() > 0) {
    if (!out.sub_results.empty()) {
      const std::size_t pad = (4 - (r.pos() - data_start) % 4) % 4;
      if (pad > r.remaining()) return wire_fail(WireError::BadLength, "padding truncated");
      r.skip(pad);
    }
    BlockView sv;
    if (auto st = read_block(r, sv); !st) return st;
    if (sv.type != block::kWriteResHeader)
      return wire_fail(WireError::BadBlockType, "not an IODWriteResHeader");
    if (auto st = decode_block(sv, out.sub_results.emplace_back()); !st) return st;
  }
  return kWireOk;
}

std::vector<std::uint8_t> encode_read_request(const RecordRequestHeader& h) {
  std::vector<std::uint8_t> out;
  encode_read_request_to(out, h);
  return out;
}

void encode_read_request_to(std::vector<std::uint8_t>& out, const RecordRequestHeader& h) {
  out.clear();
  ByteBuilder b(out);
  encode_block(b, block::kReadReqHeader, h);
}

WireStatus decode_read_request(std::span<const std::uint8_t> args, RecordRequestHeader& out) {
  ByteReader r(args);
  BlockView v;
  if (auto st = read_block(r, v); !st) return st;
  if (v.type != block::kReadReqHeader)
    return wire_fail(WireError::BadBlockType, "not an IODReadReqHeader");
  if (auto st = decode_block(v, out); !st) return st;
  if (r.remaining() != 0) return wire_fail(WireError::BadLength, "bytes after IODReadReqHeader");
  return kWireOk;
}

std::vector<std::uint8_t> encode_read_response(const RecordResponseHeader& h,
                                               std::span<const std::uint8_t> data) {
  std::vector<std::uint8_t> out;
  encode_read_response_to(out, h, data);
  return out;
}

void encode_read_response_to(std::vector<std::uint8_t>& out, const RecordResponseHeader& h,
                             std::span<const std::uint8_t> data) {
  out.clear();
  ByteBuilder b(out);
  RecordResponseHeader hh = h;
  hh.record_data_length = static_cast<std::uint32_t>(data.size());
  encode_block(b, block::kReadResHeader, hh);
  b.bytes(data);
}

WireStatus decode_read_response(std::span<const std::uint8_t> args, RecordResponseHeader& out,
                                std::span<const std::uint8_t>& data) {
  ByteReader r(args);
  BlockView v;
  if (auto st = read_block(r, v); !st) return st;
  if (v.type != block::kReadResHeader)
    return wire_fail(WireError::BadBlockType, "not an IODReadResHeader");
  if (auto st = decode_block(v, out); !st) return st;
  if (out.record_data_length != r.remaining())
    return wire_fail(WireError::BadLength, "RecordDataLength disagrees with the data");
  data = r.bytes(out.record_data_length);
  return kWireOk;
}

// --- Control ----------------------------------------------------------------------

void encode_block(ByteBuilder& b, const ControlBlock& c) {
  const auto s = begin_block(b, c.block_type);
  b.zeros(2);
  put_uuid(b, c.ar_uuid);
  b.u16(c.session_key);
  b.zeros(2);  // reserved (AlarmSequenceNumber in release variants)
  b.u16(c.command);
  b.u16(c.properties);
  end_block(b, s);
}

std::vector<std::uint8_t> encode_control(const ControlBlock& c) {
  std::vector<std::uint8_t> out;
  ByteBuilder b(out);
  encode_block(b, c);
  return out;
}

WireStatus decode_control(std::span<const std::uint8_t> args, ControlBlock& out) {
  ByteReader r(args);
  BlockView v;
  if (auto st = read_block(r, v); !st) return st;
  switch (v.type) {
    case block::kPrmEndReq:
    case block::kPrmEndRes:
    case block::kApplicationReadyReq:
    case block::kApplicationReadyRes:
    case block::kReleaseReq:
    case block::kReleaseRes:
      break;
    default:
      return wire_fail(WireError::BadBlockType, "not a control block");
  }
  if (auto st = need_type(v, v.type); !st) return st;
  if (v.body.size() != 26) return wire_fail(WireError::BadLength, "control block not 28 bytes");
  ByteReader c(v.body);
  out.block_type = v.type;
  c.skip(2);
  out.ar_uuid = get_uuid(c);
  out.session_key = c.u16();
  c.skip(2);
  out.command = c.u16();
  out.properties = c.u16();
  return finish(c, "control block truncated");
}

ControlBlock control_response_for(const ControlBlock& req) {
  ControlBlock res = req;
  res.block_type = static_cast<std::uint16_t>(req.block_type | 0x8000);
  res.command = control::kDone;
  res.properties = 0;
  return res;
}

}  // namespace plc::profinet

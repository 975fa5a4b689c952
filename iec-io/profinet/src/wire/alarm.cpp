// RTA PDUs and the alarm blocks (IEC 61158-6-10 §4.9, AlarmNotification /
// AlarmAck blocks of §5.2.4).
#include "plc/profinet/wire/alarm.hpp"

namespace plc::profinet {

AlarmAck ack_for(const AlarmNotification& n) {
  return {n.high_priority, n.alarm_type, n.api, n.slot, n.subslot, n.alarm_specifier, PnioStatus{}};
}

namespace {

void put_rta_header(ByteBuilder& b, const RtaHeader& h, std::uint16_t var_len) {
  b.u16(h.dst_endpoint);
  b.u16(h.src_endpoint);
  b.u8(static_cast<std::uint8_t>((rta::kVersion << 4) | (h.pdu_type & 0x0F)));
  b.u8(h.add_flags);
  b.u16(h.send_seq);
  b.u16(h.ack_seq);
  b.u16(var_len);
}

std::vector<std::uint8_t> rta_frame(const Mac& dst, const Mac& src, bool high, const RtaHeader& h,
                                    std::span<const std::uint8_t> sdu,
                                    std::optional<std::uint16_t> vlan) {
  std::vector<std::uint8_t> pdu;
  ByteBuilder b(pdu);
  put_rta_header(b, h, static_cast<std::uint16_t>(sdu.size()));
  b.bytes(sdu);
  return build_pn_frame(dst, src, high ? frame_id::kAlarmHigh : frame_id::kAlarmLow, pdu, vlan);
}

}  // namespace

std::vector<std::uint8_t> encode_alarm_notification(const Mac& dst, const Mac& src,
                                                    const RtaHeader& h, const AlarmNotification& n,
                                                    std::optional<std::uint16_t> vlan) {
  std::vector<std::uint8_t> sdu;
  ByteBuilder b(sdu);
  const auto s = begin_block(
      b, n.high_priority ? block::kAlarmNotificationHigh : block::kAlarmNotificationLow);
  b.u16(n.alarm_type);
  b.u32(n.api);
  b.u16(n.slot);
  b.u16(n.subslot);
  b.u32(n.module_ident);
  b.u32(n.submodule_ident);
  b.u16(n.alarm_specifier);
  if (n.user_structure_identifier) {
    b.u16(*n.user_structure_identifier);
    b.bytes(n.data);
  }
  end_block(b, s);
  RtaHeader hh = h;
  hh.pdu_type = rta::kTypeData;
  return rta_frame(dst, src, n.high_priority, hh, sdu, vlan);
}

std::vector<std::uint8_t> encode_alarm_ack(const Mac& dst, const Mac& src, const RtaHeader& h,
                                           const AlarmAck& a, std::optional<std::uint16_t> vlan) {
  std::vector<std::uint8_t> sdu;
  ByteBuilder b(sdu);
  const auto s = begin_block(b, a.high_priority ? block::kAlarmAckHigh : block::kAlarmAckLow);
  b.u16(a.alarm_type);
  b.u32(a.api);
  b.u16(a.slot);
  b.u16(a.subslot);
  b.u16(a.alarm_specifier);
  put_pnio_status(b, a.status);
  end_block(b, s);
  RtaHeader hh = h;
  hh.pdu_type = rta::kTypeData;
  return rta_frame(dst, src, a.high_priority, hh, sdu, vlan);
}

std::vector<std::uint8_t> encode_rta_ack(const Mac& dst, const Mac& src, bool high,
                                         const RtaHeader& h, std::optional<std::uint16_t> vlan) {
  return rta_frame(dst, src, high, h, {}, vlan);
}

std::vector<std::uint8_t> encode_rta_error(const Mac& dst, const Mac& src, bool high,
                                           const RtaHeader& h, const PnioStatus& status,
                                           std::optional<std::uint16_t> vlan) {
  RtaHeader hh = h;
  hh.pdu_type = rta::kTypeErr;
  const std::uint8_t sdu[] = {status.error_code, status.error_decode, status.error_code1,
                              status.error_code2};
  return rta_frame(dst, src, high, hh, sdu, vlan);
}

WireStatus decode_rta(std::uint16_t fid, std::span<const std::uint8_t> pdu, RtaPdu& out) {
  if (!is_alarm(fid)) return wire_fail(WireError::BadFrameId, "not an alarm FrameID");
  out = RtaPdu{};
  out.frame_id = fid;
  const bool high = fid == frame_id::kAlarmHigh;
  ByteReader r(pdu);
  out.header.dst_endpoint = r.u16();
  out.header.src_endpoint = r.u16();
  const std::uint8_t type = r.u8();
  out.header.pdu_type = type & 0x0F;
  out.header.add_flags = r.u8();
  out.header.send_seq = r.u16();
  out.header.ack_seq = r.u16();
  const std::uint16_t var_len = r.u16();
  if (r.failed()) return wire_fail(WireError::Truncated, "RTA header truncated");
  if ((type >> 4) != rta::kVersion) return wire_fail(WireError::BadHeader, "RTA version not 1");
  if (out.header.pdu_type < rta::kTypeData || out.header.pdu_type > rta::kTypeErr)
    return wire_fail(WireError::BadHeader, "unknown RTA PDU type");
  const auto sdu = r.bytes(var_len);  // frame padding after it is ignored
  if (r.failed()) return wire_fail(WireError::BadLength, "VarPartLen beyond the frame");
  switch (out.header.pdu_type) {
    case rta::kTypeAck:
    case rta::kTypeNack:
      if (var_len != 0) return wire_fail(WireError::BadLength, "ACK/NACK-RTA with data");
      return kWireOk;
    case rta::kTypeErr: {
      if (var_len < 4) return wire_fail(WireError::BadLength, "ERR-RTA without PNIOStatus");
      ByteReader e(sdu);
      out.error = get_pnio_status(e);
      return kWireOk;
    }
    default:
      break;
  }
  ByteReader br(sdu);
  BlockView v;
  if (auto st = read_block(br, v); !st) return st;
  if (v.version_high != 1 || v.version_low != 0)
    return wire_fail(WireError::BadBlockVersion, "alarm block version not 1.0");
  ByteReader b(v.body);
  if (v.type == block::kAlarmNotificationHigh || v.type == block::kAlarmNotificationLow) {
    if ((v.type == block::kAlarmNotificationHigh) != high)
      return wire_fail(WireError::BadBlockType, "alarm priority does not fit the FrameID");
    AlarmNotification n;
    n.high_priority = high;
    n.alarm_type = b.u16();
    n.api = b.u32();
    n.slot = b.u16();
    n.subslot = b.u16();
    n.module_ident = b.u32();
    n.submodule_ident = b.u32();
    n.alarm_specifier = b.u16();
    if (b.failed()) return wire_fail(WireError::Truncated, "AlarmNotification truncated");
    if (b.remaining() >= 2) {
      n.user_structure_identifier = b.u16();
      const auto d = b.rest();
      n.data.assign(d.begin(), d.end());
    } else if (b.remaining() != 0) {
      return wire_fail(WireError::BadLength, "AlarmNotification with a stray byte");
    }
    out.notification = std::move(n);
  } else if (v.type == block::kAlarmAckHigh || v.type == block::kAlarmAckLow) {
    if ((v.type == block::kAlarmAckHigh) != high)
      return wire_fail(WireError::BadBlockType, "alarm priority does not fit the FrameID");
    AlarmAck a;
    a.high_priority = high;
    a.alarm_type = b.u16();
    a.api = b.u32();
    a.slot = b.u16();
    a.subslot = b.u16();
    a.alarm_specifier = b.u16();
    a.status = get_pnio_status(b);
    if (b.failed()) return wire_fail(WireError::Truncated, "AlarmAck truncated");
    out.ack = a;
  } else {
    return wire_fail(WireError::BadBlockType, "DATA-RTA without an alarm block");
  }
  return kWireOk;
}

}  // namespace plc::profinet

#include "plc/profinet/wire/ethernet.hpp"

#include <algorithm>

namespace plc::profinet {

WireStatus decode_pn_frame(std::span<const std::uint8_t> frame, PnFrameView& out) {
  ByteReader r(frame);
  const auto dst = r.bytes(6);
  const auto src = r.bytes(6);
  std::uint16_t type = r.u16();
  out.vlan_tci.reset();
  if (!r.failed() && type == kEtherTypeVlan) {
    out.vlan_tci = r.u16();
    type = r.u16();
  }
  out.frame_id = r.u16();
  if (r.failed()) return wire_fail(WireError::Truncated, "frame shorter than its header");
  if (type != kEtherTypeProfinet) return wire_fail(WireError::BadEtherType, "not EtherType 0x8892");
  std::copy(dst.begin(), dst.end(), out.dst.begin());
  std::copy(src.begin(), src.end(), out.src.begin());
  out.pdu = r.rest();
  return kWireOk;
}

std::size_t encode_pn_header(std::span<std::uint8_t> out, const Mac& dst, const Mac& src,
                             std::uint16_t frame_id, std::optional<std::uint16_t> vlan_tci) {
  ByteWriter w(out);
  w.bytes(dst);
  w.bytes(src);
  if (vlan_tci) {
    w.u16(kEtherTypeVlan);
    w.u16(*vlan_tci);
  }
  w.u16(kEtherTypeProfinet);
  w.u16(frame_id);
  return w.failed() ? 0 : w.pos();
}

std::size_t pad_frame(std::span<std::uint8_t> out, std::size_t length) {
  if (length >= kMinFrameLength) return length <= out.size() ? length : 0;
  if (out.size() < kMinFrameLength) return 0;
  std::fill(out.begin() + static_cast<std::ptrdiff_t>(length),
            out.begin() + static_cast<std::ptrdiff_t>(kMinFrameLength), std::uint8_t{0});
  return kMinFrameLength;
}

std::vector<std::uint8_t> build_pn_frame(const Mac& dst, const Mac& src, std::uint16_t frame_id,
                                         std::span<const std::uint8_t> pdu,
                                         std::optional<std::uint16_t> vlan_tci) {
  std::vector<std::uint8_t> f(kEthernetHeaderLength + kVlanTagLength + 2 + pdu.size());
  const std::size_t h = encode_pn_header(f, dst, src, frame_id, vlan_tci);
  std::copy(pdu.begin(), pdu.end(), f.begin() + static_cast<std::ptrdiff_t>(h));
  f.resize(std::max(h + pdu.size(), kMinFrameLength), 0);
  return f;
}

}  // namespace plc::profinet

#include "plc/profinet/wire/ethernet.hpp"

#include <algorithm>
#include <cstring>

namespace plc::profinet {

namespace {
void put_be16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v >> 8);
  p[1] = static_cast<std::uint8_t>(v);
}
}  // namespace

std::size_t encode_pn_header(std::span<std::uint8_t> out, const Mac& dst, const Mac& src,
                             std::uint16_t frame_id, std::optional<std::uint16_t> vlan_tci) {
  const std::size_t n = kEthernetHeaderLength + (vlan_tci ? kVlanTagLength : 0) + 2;
  if (out.size() < n) return 0;
  std::uint8_t* p = out.data();
  std::copy(dst.begin(), dst.end(), p);
  std::copy(src.begin(), src.end(), p + 6);
  std::size_t at = 12;
  if (vlan_tci) {
    put_be16(p + at, kEtherTypeVlan);
    put_be16(p + at + 2, *vlan_tci);
    at += kVlanTagLength;
  }
  put_be16(p + at, kEtherTypeProfinet);
  put_be16(p + at + 2, frame_id);
  return n;
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

// Cyclic RT frames (RT_CLASS_1, and RT_CLASS_2 alike) and the IO data
// object layout (IEC 61158-6-10 §4.7, IOCRBlockReq:
// IODataObjectFrameOffset / IOCSFrameOffset).
#include "plc/profinet/wire/cyclic.hpp"

#include <algorithm>
#include <utility>

namespace plc::profinet {

const IoDataObject* IocrLayout::find(std::uint32_t api, std::uint16_t slot,
                                     std::uint16_t subslot) const {
  for (const auto& o : data)
    if (o.api == api && o.slot == slot && o.subslot == subslot) return &o;
  return nullptr;
}

const IocsSlot* IocrLayout::find_iocs(std::uint32_t api, std::uint16_t slot,
                                      std::uint16_t subslot) const {
  for (const auto& o : iocs)
    if (o.api == api && o.slot == slot && o.subslot == subslot) return &o;
  return nullptr;
}

namespace {

// Calls f(api, slot, submodule) for every expected submodule in order.
template <class F>
void each_submodule(std::span<const ExpectedSubmoduleBlockReq> expected, F&& f) {
  for (const auto& blk : expected)
    for (const auto& m : blk.modules)
      for (const auto& sm : m.submodules) f(m.api, m.slot, sm);
}

// Input-CR membership: input data or none at all (NO_IO gets a lone IOPS).
bool in_input_cr(const ExpectedSubmodule& sm) { return sm.has_input(); }
bool in_output_cr(const ExpectedSubmodule& sm) { return sm.has_output(); }

}  // namespace

WireStatus compute_layout(std::span<const ExpectedSubmoduleBlockReq> expected, CyclicLayout& out) {
  out = CyclicLayout{};
  std::size_t in_pos = 0, out_pos = 0;
  each_submodule(expected, [&](std::uint32_t api, std::uint16_t slot, const ExpectedSubmodule& sm) {
    if (in_input_cr(sm)) {
      out.input.data.push_back(
          {api, slot, sm.subslot, static_cast<std::uint16_t>(in_pos), sm.input_length});
      in_pos += sm.input_length + 1u;
    }
    if (in_output_cr(sm)) {
      out.output.data.push_back(
          {api, slot, sm.subslot, static_cast<std::uint16_t>(out_pos), sm.output_length});
      out_pos += sm.output_length + 1u;
    }
  });
  // The consumer states: each CR carries one IOCS per data object of the
  // other direction.
  for (const auto& o : out.output.data) {
    out.input.iocs.push_back({o.api, o.slot, o.subslot, static_cast<std::uint16_t>(in_pos)});
    ++in_pos;
  }
  for (const auto& o : out.input.data) {
    out.output.iocs.push_back({o.api, o.slot, o.subslot, static_cast<std::uint16_t>(out_pos)});
    ++out_pos;
  }
  if (in_pos > iocr::kMaxCSduLength || out_pos > iocr::kMaxCSduLength)
    return wire_fail(WireError::BadLength, "IO data above 1440 bytes per frame");
  out.input.c_sdu_length = static_cast<std::uint16_t>(std::max(in_pos, iocr::kMinCSduLength));
  out.output.c_sdu_length = static_cast<std::uint16_t>(std::max(out_pos, iocr::kMinCSduLength));
  return kWireOk;
}

void apply_layout(const IocrLayout& layout, IocrBlockReq& req) {
  req.apis.clear();
  auto api_entry = [&](std::uint32_t api) -> IocrApi& {
    for (auto& a : req.apis)
      if (a.api == api) return a;
    req.apis.push_back(IocrApi{api, {}, {}});
    return req.apis.back();
  };
  for (const auto& o : layout.data)
    api_entry(o.api).data_objects.push_back({o.slot, o.subslot, o.offset});
  for (const auto& o : layout.iocs) api_entry(o.api).iocs.push_back({o.slot, o.subslot, o.offset});
  req.data_length = layout.c_sdu_length;
}

WireStatus layout_from_iocr(const IocrBlockReq& req,
                            std::span<const ExpectedSubmoduleBlockReq> expected, IocrLayout& out) {
  out = IocrLayout{};
  const bool input = req.iocr_type == iocr::kTypeInput;
  if (!input && req.iocr_type != iocr::kTypeOutput)
    return wire_fail(WireError::BadValue, "IOCRType neither input nor output");
  if (req.data_length > iocr::kMaxCSduLength)
    return wire_fail(WireError::BadLength, "IOCR DataLength above 1440");
  // The frame's C_SDU is never shorter than 40 bytes, also where a device
  // takes a shorter DataLength (p-net does not check it for RT_CLASS_2):
  // the entries are checked against DataLength, the frame has 40.
  out.c_sdu_length =
      static_cast<std::uint16_t>(std::max<std::size_t>(req.data_length, iocr::kMinCSduLength));
  // Which submodule owns each byte: the bytes of two submodules must not
  // overlap; a submodule's IOCS on its own data is not refused (p-net
  // compares each submodule only with the others).
  std::vector<int> owner(req.data_length, -1);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> owners;  // (api, slot << 16 | subslot)
  auto owner_of = [&](std::uint32_t api, std::uint16_t slot, std::uint16_t subslot) {
    const std::pair<std::uint32_t, std::uint32_t> key{api, std::uint32_t{slot} << 16 | subslot};
    for (std::size_t i = 0; i < owners.size(); ++i)
      if (owners[i] == key) return static_cast<int>(i);
    owners.push_back(key);
    return static_cast<int>(owners.size() - 1);
  };
  auto claim = [&](std::size_t at, std::size_t n, int who) {
    if (at + n > owner.size()) return false;
    for (std::size_t i = at; i < at + n; ++i) {
      if (owner[i] != -1 && owner[i] != who) return false;
      owner[i] = who;
    }
    return true;
  };
  auto find_sub = [&](std::uint32_t api, std::uint16_t slot,
                      std::uint16_t subslot) -> const ExpectedSubmodule* {
    for (const auto& blk : expected)
      for (const auto& m : blk.modules)
        if (m.api == api && m.slot == slot)
          for (const auto& sm : m.submodules)
            if (sm.subslot == subslot) return &sm;
    return nullptr;
  };
  // An expected submodule need not be listed: p-net runs such an AR, the
  // submodule's data (or consumer state) then simply does not travel.
  for (const auto& a : req.apis) {
    for (const auto& e : a.data_objects) {
      const auto* sm = find_sub(a.api, e.slot, e.subslot);
      if (!sm || !(input ? in_input_cr(*sm) : in_output_cr(*sm)))
        return wire_fail(WireError::BadValue, "IO data object of no expected submodule");
      if (out.find(a.api, e.slot, e.subslot))
        return wire_fail(WireError::BadValue, "IO data object listed twice");
      // DiscardIOXS: neither data nor IOPS travel for this submodule.
      if (sm->properties & submodule::kDiscardIoxs) continue;
      const std::uint16_t len = input ? sm->input_length : sm->output_length;
      if (!claim(e.frame_offset, len + 1u, owner_of(a.api, e.slot, e.subslot)))
        return wire_fail(WireError::BadLength, "IO data object overlaps or runs past DataLength");
      out.data.push_back({a.api, e.slot, e.subslot, e.frame_offset, len});
    }
    for (const auto& e : a.iocs) {
      const auto* sm = find_sub(a.api, e.slot, e.subslot);
      if (!sm || !(input ? in_output_cr(*sm) : in_input_cr(*sm)))
        return wire_fail(WireError::BadValue, "IOCS of no expected submodule");
      if (out.find_iocs(a.api, e.slot, e.subslot))
        return wire_fail(WireError::BadValue, "IOCS listed twice");
      if (sm->properties & submodule::kDiscardIoxs) continue;
      if (!claim(e.frame_offset, 1, owner_of(a.api, e.slot, e.subslot)))
        return wire_fail(WireError::BadLength, "IOCS overlaps or runs past DataLength");
      out.iocs.push_back({a.api, e.slot, e.subslot, e.frame_offset});
    }
  }
  return kWireOk;
}

namespace {
std::size_t header_length(bool vlan) {
  return kEthernetHeaderLength + (vlan ? kVlanTagLength : 0) + 2;
}
void put_apdu_status(std::uint8_t* p, const CyclicHeader& h) {
  p[0] = static_cast<std::uint8_t>(h.cycle_counter >> 8);
  p[1] = static_cast<std::uint8_t>(h.cycle_counter);
  p[2] = h.data_status;
  p[3] = h.transfer_status;
}
}  // namespace

std::span<std::uint8_t> cyclic_c_sdu(std::span<std::uint8_t> frame, std::size_t c_sdu_length,
                                     bool vlan) {
  if (c_sdu_length > iocr::kMaxCSduLength) return {};
  if (cyclic_frame_length(c_sdu_length, vlan) > frame.size()) return {};
  return frame.subspan(header_length(vlan), c_sdu_length);
}

std::size_t finish_cyclic(std::span<std::uint8_t> frame, const CyclicHeader& h,
                          std::size_t c_sdu_length) {
  const bool vlan = h.vlan_tci.has_value();
  if (c_sdu_length < iocr::kMinCSduLength || c_sdu_length > iocr::kMaxCSduLength) return 0;
  const std::size_t len = cyclic_frame_length(c_sdu_length, vlan);
  if (len > frame.size()) return 0;
  if (encode_pn_header(frame, h.dst, h.src, h.frame_id, h.vlan_tci) != header_length(vlan))
    return 0;
  put_apdu_status(frame.data() + header_length(vlan) + c_sdu_length, h);
  return len;
}

std::size_t encode_cyclic(std::span<std::uint8_t> out, const CyclicHeader& h,
                          std::span<const std::uint8_t> c_sdu) {
  const std::size_t n = std::max(c_sdu.size(), iocr::kMinCSduLength);
  auto dst = cyclic_c_sdu(out, n, h.vlan_tci.has_value());
  if (dst.empty()) return 0;
  std::copy(c_sdu.begin(), c_sdu.end(), dst.begin());
  std::fill(dst.begin() + static_cast<std::ptrdiff_t>(c_sdu.size()), dst.end(), std::uint8_t{0});
  return finish_cyclic(out, h, n);
}

WireStatus decode_cyclic(std::span<const std::uint8_t> frame, std::size_t c_sdu_length,
                         CyclicView& out) {
  PnFrameView v;
  if (auto st = decode_pn_frame(frame, v); !st) return st;
  return decode_cyclic(v, c_sdu_length, out);
}

}  // namespace plc::profinet

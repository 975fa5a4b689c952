// The IOCRs' IO data object and IOCS entries against the expected
// submodules, and the byte areas they make in each C_SDU, after p-net's
// pf_cmdev_iocr_setup_desc (the areas) and pf_cmdev_check_iocr_apis (the
// checks, ErrorCode1 0x02). What p-net does not ask: that every expected
// submodule be listed (each needs to be in some IOCR, checked with the
// expected submodules, 0x03 0x0A); a missing IOCS or data object is
// accepted and connect_warnings() says so.
#include <algorithm>

#include "connect_parts.hpp"
#include "plc/profinet/device/connect_check.hpp"

namespace plc::profinet::connect_detail {

namespace {

using connect_error::kIocrBlock;

std::optional<PnioStatus> fail(std::uint8_t code2) { return connect_refusal(kIocrBlock, code2); }

bool input_cr(const IocrBlockReq& c) {
  return c.iocr_type == iocr::kTypeInput || c.iocr_type == 3;  // input or multicast provider
}

bool same_place(const IocrEntry& a, const IocrEntry& b) {
  return a.slot == b.slot && a.subslot == b.subslot;
}

// An IO data object's submodule must have data in this CR's direction.
bool data_fits(std::uint16_t type, bool in_cr) {
  if (in_cr) return type != submodule::kTypeOutput;
  return type == submodule::kTypeOutput || type == submodule::kTypeInputOutput;
}
// An IOCS entry's submodule must have data in the other direction.
bool iocs_fits(std::uint16_t type, bool in_cr) { return data_fits(type, !in_cr); }

std::optional<PnioStatus> check_api_entries(const IocrApi& a, const ExpectedApi& api, bool in_cr) {
  if (a.data_objects.empty() && a.iocs.empty()) return fail(21);
  for (std::size_t i = 0; i < a.data_objects.size(); ++i)
    for (std::size_t j = 0; j < a.data_objects.size(); ++j)
      if (i != j && same_place(a.data_objects[i], a.data_objects[j])) return fail(23);
  for (const IocrEntry& e : a.data_objects) {
    const ExpectedModule* m = find_module(api, e.slot);
    if (!m) return fail(22);
    const ExpectedSubmodule* s = find_submodule(*m, e.subslot);
    if (!s) return fail(23);
    if (!data_fits(s->type(), in_cr)) return fail(23);
  }
  for (std::size_t i = 0; i < a.iocs.size(); ++i)
    for (std::size_t j = 0; j < a.iocs.size(); ++j)
      if (i != j && same_place(a.iocs[i], a.iocs[j])) return fail(27);
  for (const IocrEntry& e : a.iocs) {
    const ExpectedModule* m = find_module(api, e.slot);
    const ExpectedSubmodule* s = m ? find_submodule(*m, e.subslot) : nullptr;
    if (!s) return fail(27);
    if (!iocs_fits(s->type(), in_cr)) return fail(27);
    // 0x1C cannot fail once the expected submodule passed (0x03 0x0C).
    if (s->type() == submodule::kTypeInputOutput && s->wire_descriptions().size() != 2)
      return fail(28);
  }
  return std::nullopt;
}

// Bounds (0x18 data/IOPS, 0x1C IOCS), then overlap with the submodules laid
// out before it: its data or IOPS on another's bytes 0x18, its IOCS 0x1C.
std::optional<PnioStatus> check_areas(const std::vector<SubmoduleAreas>& areas,
                                      std::uint32_t data_length) {
  for (std::size_t i = 0; i < areas.size(); ++i) {
    const SubmoduleAreas& x = areas[i];
    if (x.data.end() > data_length || x.iops.end() > data_length) return fail(24);
    if (x.iocs.end() > data_length) return fail(28);
    auto hits = [&](const Area& a) {
      for (std::size_t j = 0; j < i; ++j) {
        const SubmoduleAreas& y = areas[j];
        if (overlap(a, y.data) || overlap(a, y.iocs) || overlap(a, y.iops)) return true;
      }
      return false;
    };
    if (hits(x.data) || hits(x.iops)) return fail(24);
    if (hits(x.iocs)) return fail(28);
  }
  return std::nullopt;
}

}  // namespace

bool overlap(const Area& a, const Area& b) {
  if (a.length == 0 || b.length == 0) return false;
  return a.start < b.end() && b.start < a.end();
}

std::vector<SubmoduleAreas> lay_out(const IocrBlockReq& cr, const std::vector<ExpectedApi>& apis) {
  const bool in_cr = input_cr(cr);
  const std::uint16_t own = in_cr ? submodule::kDataInput : submodule::kDataOutput;
  const std::uint16_t other = in_cr ? submodule::kDataOutput : submodule::kDataInput;
  std::vector<SubmoduleAreas> out;
  auto entry = [&](std::uint32_t api, const IocrEntry& e) -> SubmoduleAreas& {
    for (auto& x : out)
      if (x.api == api && x.slot == e.slot && x.subslot == e.subslot) return x;
    out.push_back({api, e.slot, e.subslot, {}, {}, {}});
    return out.back();
  };
  auto description = [](const ExpectedSubmodule& s, std::uint16_t dir) {
    std::optional<DataDescription> found;
    for (const auto& d : s.wire_descriptions())
      if (d.direction == dir && !found) found = d;
    return found;
  };
  for (const IocrApi& a : cr.apis)
    for (const IocrEntry& e : a.data_objects) {
      const ExpectedSubmodule* s = find_expected(apis, a.api, e.slot, e.subslot);
      if (!s || !data_fits(s->type(), in_cr)) continue;
      const auto d = description(*s, own);
      if (!d) continue;
      SubmoduleAreas& x = entry(a.api, e);
      if (s->properties & submodule::kDiscardIoxs) continue;  // no data, no IOPS
      // Reduce{Input,Output}SubmoduleDataLength passes 0x03 0x0C only where
      // that direction has no data (length 0): nothing to reduce here.
      x.data = {e.frame_offset, d->length};
      x.iops = {x.data.end(), d->length_iops};
    }
  for (const IocrApi& a : cr.apis)
    for (const IocrEntry& e : a.iocs) {
      const ExpectedSubmodule* s = find_expected(apis, a.api, e.slot, e.subslot);
      if (!s || !iocs_fits(s->type(), in_cr)) continue;
      const auto d = description(*s, other);
      if (!d) continue;
      SubmoduleAreas& x = entry(a.api, e);
      if (s->properties & submodule::kDiscardIoxs) continue;
      x.iocs = {e.frame_offset, d->length_iocs};
    }
  return out;
}

std::optional<PnioStatus> check_iocr_entries(const ConnectRequest& req,
                                             const std::vector<ExpectedApi>& apis) {
  for (const IocrBlockReq& c : req.iocrs) {
    for (const IocrApi& a : c.apis) {
      const ExpectedApi* api = find_api(apis, a.api);
      if (!api) return fail(20);
      if (auto e = check_api_entries(a, *api, input_cr(c))) return e;
    }
    if (auto e = check_areas(lay_out(c, apis), c.data_length)) return e;
  }
  return std::nullopt;
}

}  // namespace plc::profinet::connect_detail

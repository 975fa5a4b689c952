// connect_warnings() (connect_check.hpp): what a Connect that p-net (and so
// check_connect()) accepts does against IEC 61158-6-10. We accept it as
// p-net does, so that what runs against a p-net device runs against ours,
// and say so once per Connect (pndevsim prints one line each).
#include <cstdio>

#include "connect_parts.hpp"
#include "plc/profinet/device/connect_check.hpp"

namespace plc::profinet {

namespace {

std::string where(std::uint32_t api, std::uint16_t slot, std::uint16_t subslot) {
  char b[64];
  std::snprintf(b, sizeof b, "API 0x%X slot %u subslot 0x%04X", static_cast<unsigned>(api),
                static_cast<unsigned>(slot), static_cast<unsigned>(subslot));
  return b;
}

bool listed(const std::vector<IocrEntry>& entries, std::uint16_t slot, std::uint16_t subslot) {
  for (const auto& e : entries)
    if (e.slot == slot && e.subslot == subslot) return true;
  return false;
}

// IEC 61158-6-10 IOCRBlockReq: a CR carries an IO data object for every
// submodule with data in its direction (NO_IO ones in the input CR) and an
// IOCS for every submodule of the other direction. p-net only asks that
// each expected submodule be named in some IOCR.
void missing_entries(const IocrBlockReq& c, const char* cr,
                     const std::vector<connect_detail::ExpectedApi>& apis,
                     std::vector<std::string>& out) {
  const bool in_cr = c.iocr_type == iocr::kTypeInput;
  for (const auto& api : apis) {
    const IocrApi* a = nullptr;
    for (const auto& x : c.apis)
      if (x.api == api.api) a = &x;
    for (const ExpectedModule* m : api.modules)
      for (const ExpectedSubmodule& s : m->submodules) {
        if (s.properties & submodule::kDiscardIoxs) continue;
        const bool wants_data = in_cr ? s.has_input() : s.has_output();
        const bool wants_iocs = in_cr ? s.has_output() : s.has_input();
        if (wants_data && !(a && listed(a->data_objects, m->slot, s.subslot)))
          out.push_back(std::string(cr) + " lists no IO data object for " +
                        where(api.api, m->slot, s.subslot) +
                        ": its data is not exchanged (IEC 61158-6-10 IOCRBlockReq: an IO data "
                        "object for every submodule with data of the CR's direction); accepted "
                        "as p-net accepts it");
        if (wants_iocs && !(a && listed(a->iocs, m->slot, s.subslot)))
          out.push_back(std::string(cr) + " lists no IOCS for " +
                        where(api.api, m->slot, s.subslot) +
                        ": its consumer state is not sent (IEC 61158-6-10 IOCRBlockReq: an IOCS "
                        "for every submodule of the other direction); accepted as p-net "
                        "accepts it");
      }
  }
}

}  // namespace

std::vector<std::string> connect_warnings(const ConnectRequest& req) {
  std::vector<std::string> out;
  const auto apis = connect_detail::expected_apis(req);
  for (const IocrBlockReq& c : req.iocrs) {
    const char* cr = c.iocr_type == iocr::kTypeInput ? "input CR" : "output CR";
    const std::uint32_t rt = rt_class_of(c);
    const bool frame_class =
        rt == rt_class::kClass1 || rt == rt_class::kClass2 || rt == rt_class::kClass3;
    char b[256];
    if (c.iocr_tag_header & 0x0800U) {
      std::snprintf(b, sizeof b,
                    "%s: IOCRTagHeader 0x%04X has VLAN ID bit 11 set (IEC 61158-6-10 "
                    "IOCRTagHeader: IOCRVLANID, bits 0..11, is 0); accepted as p-net accepts "
                    "it (it reads bits 0..10)",
                    cr, static_cast<unsigned>(c.iocr_tag_header));
      out.emplace_back(b);
    }
    const std::uint64_t hold_us =
        std::uint64_t{c.data_hold_factor} * c.reduction_ratio * c.send_clock_factor * 1000U / 32U;
    if ((frame_class && hold_us > 1920000U) || (rt == rt_class::kUdp && hold_us > 61440000U)) {
      std::snprintf(b, sizeof b,
                    "%s: data hold time %llu us is above the limit (IEC 61158-6-10 IOCRBlockReq: "
                    "DataHoldFactor, at most %s); accepted as p-net accepts it (its 32-bit "
                    "product wraps)",
                    cr, static_cast<unsigned long long>(hold_us),
                    rt == rt_class::kUdp ? "61.44 s" : "1.92 s");
      out.emplace_back(b);
    }
    if (rt != rt_class::kClass1 && rt != rt_class::kUdp && c.data_length < iocr::kMinCSduLength) {
      std::snprintf(b, sizeof b,
                    "%s: DataLength %u is below 40 (IEC 61158-6-10 C_SDU: 40..1440 octets); "
                    "accepted as p-net accepts it for RT class %u: the frames carry 40",
                    cr, static_cast<unsigned>(c.data_length), static_cast<unsigned>(rt));
      out.emplace_back(b);
    }
    if (rt == rt_class::kUdp)
      out.push_back(std::string(cr) +
                    ": RT_CLASS_UDP (IEC 61158-6-10 IOCRProperties.RTClass: RT frames over "
                    "UDP); accepted as p-net accepts it, but this device, like p-net, sends and "
                    "takes cyclic data as Ethernet frames only");
    if (rt == rt_class::kStream)
      out.push_back(std::string(cr) +
                    ": RT_CLASS_STREAM (IEC 61158-6-10 IOCRProperties.RTClass: TSN streams); "
                    "accepted as p-net accepts it, the frames go without TSN scheduling");
    missing_entries(c, cr, apis, out);
    for (const auto& x : connect_detail::lay_out(c, apis))
      if (connect_detail::overlap(x.iocs, x.data) || connect_detail::overlap(x.iocs, x.iops))
        out.push_back(std::string(cr) + ": the IOCS of " + where(x.api, x.slot, x.subslot) +
                      " lies on its own data or IOPS (IEC 61158-6-10 IOCRBlockReq: IO data "
                      "objects and IOCS do not overlap); accepted as p-net accepts it (it "
                      "compares each submodule with the others only)");
  }
  return out;
}

}  // namespace plc::profinet

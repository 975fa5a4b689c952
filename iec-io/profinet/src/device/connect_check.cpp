// The Connect checks of p-net's pf_cmdev.c (see connect_check.hpp). The
// numbers in the refusals are p-net's ErrorCode2 values for the field that
// failed; comments name the p-net function each group comes from.
#include "plc/profinet/device/connect_check.hpp"

#include <algorithm>
#include <cctype>
#include <vector>

namespace plc::profinet {

namespace {

using connect_error::kAlarmCrBlock;
using connect_error::kArBlock;
using connect_error::kCmrpc;
using connect_error::kExpectedBlock;
using connect_error::kIocrBlock;

constexpr std::uint16_t kRtClass1 = 1;
constexpr std::uint16_t kRtClassUdp = 4;
constexpr std::uint16_t kRtClassStream = 5;

std::optional<PnioStatus> fail(std::uint8_t code1, std::uint8_t code2) {
  return connect_refusal(code1, code2);
}

// pf_cmdev_check_cm_initiator_object_uuid: DEA00000-6C97-11D1-8271-...
bool initiator_object_uuid_ok(const Uuid& u) {
  return u.data1 == 0xDEA00000 && u.data2 == 0x6C97 && u.data3 == 0x11D1 && u.data4[0] == 0x82 &&
         u.data4[1] == 0x71;
}

// pf_cmdev_check_ar_param
std::optional<PnioStatus> check_ar(const ArBlockReq& ar) {
  const std::uint32_t p = ar.ar_properties;
  const bool device_access = (p >> 8) & 1U;
  const std::uint32_t companion = (p >> 9) & 3U;
  if (ar.ar_type != ar::kTypeIocarSingle) return fail(kArBlock, 4);
  if (ar.ar_uuid.is_nil()) return fail(kArBlock, 5);
  if (ar.cm_initiator_mac[0] & 0x01) return fail(kArBlock, 7);  // multicast MAC
  if (!initiator_object_uuid_ok(ar.cm_initiator_object_uuid)) return fail(kArBlock, 8);
  if ((p & 0x7U) != 1U) return fail(kArBlock, 9);      // State must be Active
  if (((p >> 4) & 1U) == 0) return fail(kArBlock, 9);  // external parameter server
  if (device_access) return fail(kArBlock, 9);         // device access only with IOSAR
  if (companion == 3) return fail(kArBlock, 9);
  if (ar.activity_timeout_factor < 1 || ar.activity_timeout_factor > 1000)
    return fail(kArBlock, 10);
  if (ar.station_name.empty() || ar.station_name.size() > 240) return fail(kArBlock, 12);
  for (const char c : ar.station_name)
    if (!std::isprint(static_cast<unsigned char>(c))) return fail(kArBlock, 13);
  return std::nullopt;
}

bool power_of_two_1_128(std::uint16_t v) {
  return v == 1 || v == 2 || v == 4 || v == 8 || v == 16 || v == 32 || v == 64 || v == 128;
}

// pf_cmdev_check_iocr_param (one IOCR). Only RT_CLASS_1 frames are
// exchanged by this device, so another RT class is refused like an
// out-of-range one (ErrorCode2 7).
std::optional<PnioStatus> check_iocr(const IocrBlockReq& c, bool startup_advanced,
                                     const DeviceDescription& dev) {
  const std::uint32_t rt_class = c.iocr_properties & 0xFU;
  const std::uint32_t reserved1 = (c.iocr_properties >> 4) & 0x1FFU;
  const std::uint32_t reserved3 = c.iocr_properties >> 24;
  if (c.iocr_type < iocr::kTypeInput || c.iocr_type > 4) return fail(kIocrBlock, 4);
  if (rt_class != kRtClassUdp && c.lt != iocr::kLtProfinet) return fail(kIocrBlock, 6);
  if (rt_class == kRtClassUdp && c.lt != 0x0800) return fail(kIocrBlock, 6);
  if (!startup_advanced && (rt_class < 1 || rt_class > kRtClassStream)) return fail(kIocrBlock, 7);
  if (startup_advanced && (rt_class < 2 || rt_class > kRtClassStream)) return fail(kIocrBlock, 7);
  if (rt_class != kRtClass1) return fail(kIocrBlock, 7);  // not supported here
  if (reserved1 != 0 || reserved3 != 0) return fail(kIocrBlock, 7);
  if (c.data_length < iocr::kMinCSduLength || c.data_length > iocr::kMaxCSduLength)
    return fail(kIocrBlock, 8);
  if ((c.iocr_type == 3 || c.iocr_type == 4) && (c.frame_id < 0xF800 || c.frame_id > 0xFBFF))
    return fail(kIocrBlock, 9);
  if (c.iocr_type == iocr::kTypeInput && !is_rt_class1(c.frame_id)) return fail(kIocrBlock, 9);
  if (!power_of_two_1_128(c.send_clock_factor)) return fail(kIocrBlock, 10);
  if (c.reduction_ratio < 1 || c.reduction_ratio > 512 ||
      (c.reduction_ratio >= 256 && c.send_clock_factor > 64) ||
      (c.reduction_ratio == 512 && c.send_clock_factor > 32) ||
      dev.min_device_interval > send_interval(c.send_clock_factor, c.reduction_ratio))
    return fail(kIocrBlock, 11);
  if (c.phase == 0 || c.phase > c.reduction_ratio) return fail(kIocrBlock, 12);
  if (c.frame_send_offset != iocr::kFrameSendOffsetBestEffort &&
      (c.frame_send_offset >= std::uint32_t{c.send_clock_factor} * 31250U ||
       c.frame_send_offset >= 0x003D0900U))
    return fail(kIocrBlock, 14);
  // DataHoldFactor 1..0x1E00 and the hold time at most 1.92 s.
  if (c.data_hold_factor < 1 || c.data_hold_factor > 0x1E00 ||
      (std::uint64_t{c.data_hold_factor} * c.reduction_ratio * c.send_clock_factor * 1000U) / 32U >
          1920000U)
    return fail(kIocrBlock, 16);
  if ((c.iocr_tag_header & 0x0FFFU) != 0) return fail(kIocrBlock, 17);  // VLAN ID 0
  if ((c.iocr_tag_header >> 13) != 6) return fail(kIocrBlock, 17);      // priority 6
  if ((c.iocr_type == 3 || c.iocr_type == 4) && (c.multicast_mac[0] & 0x01) == 0)
    return fail(kIocrBlock, 18);
  if (c.apis.empty()) return fail(kIocrBlock, 19);
  return std::nullopt;
}

const ModuleDescription* find_module(const DeviceDescription& dev, std::uint16_t slot) {
  for (const auto& m : dev.modules)
    if (m.slot == slot) return &m;
  return nullptr;
}
const SubmoduleDescription* find_submodule(const ModuleDescription& m, std::uint16_t subslot) {
  for (const auto& s : m.submodules)
    if (s.subslot == subslot) return &s;
  return nullptr;
}

bool used_in_some_iocr(const ConnectRequest& req, std::uint32_t api, std::uint16_t slot,
                       std::uint16_t subslot) {
  for (const auto& c : req.iocrs)
    for (const auto& a : c.apis) {
      if (a.api != api) continue;
      for (const auto& e : a.data_objects)
        if (e.slot == slot && e.subslot == subslot) return true;
      for (const auto& e : a.iocs)
        if (e.slot == slot && e.subslot == subslot) return true;
    }
  return false;
}

// pf_cmdev_exp_apis_configure / _exp_modules_configure / _exp_submodule_configure
std::optional<PnioStatus> check_expected(const ConnectRequest& req,
                                         const std::vector<const ExpectedModule*>& mods,
                                         const DeviceDescription& dev) {
  if (mods.empty()) return fail(kExpectedBlock, 4);
  for (std::size_t i = 0; i < mods.size(); ++i) {
    const ExpectedModule& m = *mods[i];
    for (std::size_t j = 0; j < i; ++j)
      if (mods[j]->api == m.api && mods[j]->slot == m.slot) return fail(kExpectedBlock, 6);
    if (m.slot > 0x7FFF) return fail(kExpectedBlock, 6);
    const ModuleDescription* real = find_module(dev, m.slot);
    if (!real) return fail(kExpectedBlock, 6);  // no such slot on this device
    if (m.module_ident == 0) return fail(kExpectedBlock, 7);
    if (m.submodules.empty()) return fail(kExpectedBlock, 9);
    for (std::size_t k = 0; k < m.submodules.size(); ++k) {
      const ExpectedSubmodule& s = m.submodules[k];
      for (std::size_t l = 0; l < k; ++l)
        if (m.submodules[l].subslot == s.subslot) return fail(kExpectedBlock, 10);
      if (!used_in_some_iocr(req, m.api, m.slot, s.subslot)) return fail(kExpectedBlock, 10);
      if (s.subslot > 0x9FFF) return fail(kExpectedBlock, 10);
      if (!find_submodule(*real, s.subslot)) return fail(kExpectedBlock, 10);
      if (s.subslot >= kInterfaceSubslot && m.api != 0) return fail(kExpectedBlock, 10);
      if (s.input_length > 1439 || s.output_length > 1439) return fail(kExpectedBlock, 14);
      if (s.length_iops != 1) return fail(kExpectedBlock, 15);
      if (s.length_iocs != 1) return fail(kExpectedBlock, 16);
    }
  }
  return std::nullopt;
}

const ExpectedSubmodule* find_expected(const std::vector<const ExpectedModule*>& mods,
                                       std::uint32_t api, std::uint16_t slot, std::uint16_t subslot,
                                       bool& slot_found) {
  slot_found = false;
  for (const ExpectedModule* m : mods) {
    if (m->api != api || m->slot != slot) continue;
    slot_found = true;
    for (const auto& s : m->submodules)
      if (s.subslot == subslot) return &s;
  }
  return nullptr;
}

struct Area {
  std::uint32_t start, length;
  bool iocs;
};
bool overlap(const Area& a, const Area& b) {
  if (a.length == 0 || b.length == 0) return false;
  return a.start < b.start + b.length && b.start < a.start + a.length;
}

// pf_cmdev_check_iocr_apis (after pf_cmdev_iocr_setup_desc has laid out data,
// IOPS and IOCS of every entry).
std::optional<PnioStatus> check_iocr_apis(const ConnectRequest& req,
                                          const std::vector<const ExpectedModule*>& mods) {
  for (const IocrBlockReq& c : req.iocrs) {
    const bool input_cr = c.iocr_type == iocr::kTypeInput;
    std::vector<Area> areas;
    for (const IocrApi& a : c.apis) {
      bool api_known = false;
      for (const ExpectedModule* m : mods) api_known = api_known || m->api == a.api;
      if (!api_known) return fail(kIocrBlock, 20);
      if (a.data_objects.empty() && a.iocs.empty()) return fail(kIocrBlock, 21);
      for (std::size_t i = 0; i < a.data_objects.size(); ++i) {
        const IocrEntry& e = a.data_objects[i];
        for (std::size_t j = 0; j < a.data_objects.size(); ++j)
          if (j != i && a.data_objects[j].slot == e.slot && a.data_objects[j].subslot == e.subslot)
            return fail(kIocrBlock, 23);
        bool slot_found = false;
        const ExpectedSubmodule* s = find_expected(mods, a.api, e.slot, e.subslot, slot_found);
        if (!slot_found) return fail(kIocrBlock, 22);
        if (!s) return fail(kIocrBlock, 23);
        const std::uint16_t type = s->type();
        if (!input_cr && (type == submodule::kTypeNoIo || type == submodule::kTypeInput))
          return fail(kIocrBlock, 23);
        if (input_cr && type == submodule::kTypeOutput) return fail(kIocrBlock, 23);
        const std::uint32_t len = input_cr ? s->input_length : s->output_length;
        areas.push_back({e.frame_offset, len, false});
        areas.push_back({e.frame_offset + len, s->length_iops, false});
      }
      for (std::size_t i = 0; i < a.iocs.size(); ++i) {
        const IocrEntry& e = a.iocs[i];
        for (std::size_t j = 0; j < a.iocs.size(); ++j)
          if (j != i && a.iocs[j].slot == e.slot && a.iocs[j].subslot == e.subslot)
            return fail(kIocrBlock, 27);
        bool slot_found = false;
        const ExpectedSubmodule* s = find_expected(mods, a.api, e.slot, e.subslot, slot_found);
        if (!s) return fail(kIocrBlock, 27);
        const std::uint16_t type = s->type();
        if (input_cr && (type == submodule::kTypeNoIo || type == submodule::kTypeInput))
          return fail(kIocrBlock, 27);
        if (!input_cr && type == submodule::kTypeOutput) return fail(kIocrBlock, 27);
        areas.push_back({e.frame_offset, s->length_iocs, true});
      }
    }
    for (std::size_t i = 0; i < areas.size(); ++i) {
      const Area& x = areas[i];
      if (x.start + x.length > c.data_length) return fail(kIocrBlock, x.iocs ? 28 : 24);
      for (std::size_t j = 0; j < i; ++j)
        if (overlap(x, areas[j])) return fail(kIocrBlock, x.iocs ? 28 : 24);
    }
  }
  return std::nullopt;
}

// pf_cmdev_check_alarm_cr
std::optional<PnioStatus> check_alarm_cr(const AlarmCrBlockReq& a) {
  const bool udp = (a.properties >> 1) & 1U;
  if (a.alarm_cr_type != alarm_cr::kType) return fail(kAlarmCrBlock, 4);
  if ((!udp && a.lt != iocr::kLtProfinet) || (udp && a.lt != 0x0800)) return fail(kAlarmCrBlock, 5);
  if (a.rta_timeout_factor < 1 || a.rta_timeout_factor > 100) return fail(kAlarmCrBlock, 7);
  if (a.rta_retries < 3 || a.rta_retries > 15) return fail(kAlarmCrBlock, 8);
  if (a.max_alarm_data_length < 200 || a.max_alarm_data_length > 1432)
    return fail(kAlarmCrBlock, 10);
  if ((a.tag_header_high & 0x0FFFU) != 0 || (a.tag_header_high >> 13) != 6)
    return fail(kAlarmCrBlock, 11);
  if ((a.tag_header_low & 0x0FFFU) != 0 || (a.tag_header_low >> 13) != 5)
    return fail(kAlarmCrBlock, 12);
  return std::nullopt;
}

std::vector<const ExpectedModule*> expected_modules(const ConnectRequest& req) {
  std::vector<const ExpectedModule*> out;
  for (const auto& b : req.expected)
    for (const auto& m : b.modules) out.push_back(&m);
  return out;
}

}  // namespace

std::optional<PnioStatus> check_connect(const ConnectRequest& req, const DeviceDescription& dev) {
  if (auto e = check_ar(req.ar)) return e;
  const bool advanced = (req.ar.ar_properties >> 30) & 1U;
  for (const auto& c : req.iocrs)
    if (auto e = check_iocr(c, advanced, dev)) return e;
  const auto mods = expected_modules(req);
  if (auto e = check_expected(req, mods, dev)) return e;
  if (auto e = check_iocr_apis(req, mods)) return e;
  const auto inputs = std::count_if(req.iocrs.begin(), req.iocrs.end(),
                                    [](const auto& c) { return c.iocr_type == iocr::kTypeInput; });
  const auto outputs = std::count_if(req.iocrs.begin(), req.iocrs.end(), [](const auto& c) {
    return c.iocr_type == iocr::kTypeOutput;
  });
  if (inputs == 0 || outputs == 0) return fail(kCmrpc, connect_error::kCmrpcIocrMissing);
  // One input and one output CR: the only layout this device exchanges.
  if (inputs != 1 || outputs != 1) return fail(kCmrpc, connect_error::kCmrpcWrongBlockCount);
  if (auto e = check_alarm_cr(req.alarm_cr)) return e;
  return std::nullopt;
}

std::optional<ModuleDiffBlock> module_diff(const ConnectRequest& req,
                                           const DeviceDescription& dev) {
  ModuleDiffBlock diff;
  for (const ExpectedModule* m : expected_modules(req)) {
    const ModuleDescription* real = find_module(dev, m->slot);
    ModuleDiffModule md;
    md.slot = m->slot;
    if (!real) {
      md.state = module_state::kNoModule;
    } else if (real->module_ident != m->module_ident) {
      md.state = module_state::kWrongModule;
      md.module_ident = real->module_ident;
    } else {
      md.module_ident = real->module_ident;
      for (const ExpectedSubmodule& s : m->submodules) {
        const SubmoduleDescription* rs = find_submodule(*real, s.subslot);
        if (!rs) {
          md.submodules.push_back({s.subslot, 0, submodule_state::kNoSubmodule});
        } else if (rs->submodule_ident != s.submodule_ident || rs->api != m->api ||
                   rs->input_length != s.input_length || rs->output_length != s.output_length) {
          // Our reading: an ident we have but with other data lengths cannot
          // carry the model's bytes either, so it is reported Wrong too.
          md.submodules.push_back({s.subslot, rs->submodule_ident, submodule_state::kWrong});
        }
      }
      if (md.submodules.empty()) continue;
    }
    auto api = std::find_if(diff.apis.begin(), diff.apis.end(),
                            [&](const ModuleDiffApi& a) { return a.api == m->api; });
    if (api == diff.apis.end()) {
      diff.apis.push_back({m->api, {}});
      api = diff.apis.end() - 1;
    }
    api->modules.push_back(std::move(md));
  }
  if (diff.apis.empty()) return std::nullopt;
  return diff;
}

}  // namespace plc::profinet

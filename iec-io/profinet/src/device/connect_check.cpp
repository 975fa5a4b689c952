// check_connect() (connect_check.hpp): the AR, IOCR, AlarmCR and ARRPC
// block checks and the block counts of p-net's pf_cmdev_check_apdu; the
// expected submodules and the IOCR entries are in their own files
// (connect_parts.hpp). The numbers in the refusals are p-net's ErrorCode2
// values for the field that failed; comments name the p-net function each
// group comes from.
#include "plc/profinet/device/connect_check.hpp"

#include <algorithm>
#include <cctype>

#include "connect_parts.hpp"

namespace plc::profinet {

namespace {

using connect_error::kAlarmCrBlock;
using connect_error::kArBlock;
using connect_error::kArRpcBlock;
using connect_error::kCmrpc;
using connect_error::kIocrBlock;

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

bool in(std::uint16_t v, std::uint16_t first, std::uint16_t last) {
  return v >= first && v <= last;
}

// The FrameID ranges p-net checks (IEC 61158-6-10 "FrameID"): unicast for
// an input CR, multicast for a multicast CR; RT_CLASS_STREAM is not checked.
bool unicast_frame_id_ok(std::uint32_t rt, std::uint16_t id) {
  switch (rt) {
    case rt_class::kClass1:
    case rt_class::kUdp:
      return in(id, 0xC000, 0xF7FF);
    case rt_class::kClass2:
      return in(id, 0x8000, 0xBBFF);
    case rt_class::kClass3:
      return in(id, 0x0100, 0x7FFF);
    default:
      return true;
  }
}
bool multicast_frame_id_ok(std::uint32_t rt, std::uint16_t id) {
  switch (rt) {
    case rt_class::kClass1:
    case rt_class::kUdp:
      return in(id, 0xF800, 0xFBFF);
    case rt_class::kClass2:
      return in(id, 0xBC00, 0xBFFF);
    case rt_class::kClass3:
      return in(id, 0x0100, 0x7FFF);
    default:
      return true;
  }
}

// pf_cmdev_check_iocr_param, for one IOCR. (Its first check, device access
// -> CMRPC 0x01, cannot fail here: check_ar() refused device access.)
std::optional<PnioStatus> check_iocr(const IocrBlockReq& c, const ArBlockReq& ar,
                                     const DeviceDescription& dev) {
  const std::uint32_t rt = rt_class_of(c);
  const bool advanced = (ar.ar_properties >> 30) & 1U;
  const bool udp = rt == rt_class::kUdp;
  const bool frame_class =
      rt == rt_class::kClass1 || rt == rt_class::kClass2 || rt == rt_class::kClass3;
  const bool multicast = c.iocr_type == 3 || c.iocr_type == 4;
  const std::uint32_t reserved1 = (c.iocr_properties >> 4) & 0x1FFU;
  const std::uint32_t reserved3 = c.iocr_properties >> 24;
  if (c.iocr_type < iocr::kTypeInput || c.iocr_type > 4) return fail(kIocrBlock, 4);
  if (udp ? c.lt != 0x0800 : c.lt != iocr::kLtProfinet) return fail(kIocrBlock, 6);
  // Legacy start-up: RT_CLASS_1..STREAM; advanced start-up: from RT_CLASS_2 on.
  if (rt < (advanced ? rt_class::kClass2 : rt_class::kClass1) || rt > rt_class::kStream)
    return fail(kIocrBlock, 7);
  if (reserved1 != 0 || reserved3 != 0) return fail(kIocrBlock, 7);
  // DataLength: checked for RT_CLASS_UDP (12..1440) and RT_CLASS_1 (40..1440) only.
  if ((udp && (c.data_length < 12 || c.data_length > iocr::kMaxCSduLength)) ||
      (rt == rt_class::kClass1 &&
       (c.data_length < iocr::kMinCSduLength || c.data_length > iocr::kMaxCSduLength)))
    return fail(kIocrBlock, 8);
  if (multicast && !multicast_frame_id_ok(rt, c.frame_id)) return fail(kIocrBlock, 9);
  if (c.iocr_type == iocr::kTypeInput && !unicast_frame_id_ok(rt, c.frame_id))
    return fail(kIocrBlock, 9);
  if (!power_of_two_1_128(c.send_clock_factor)) return fail(kIocrBlock, 10);
  const std::uint16_t rr = c.reduction_ratio, scf = c.send_clock_factor;
  if (frame_class && (rr < 1 || rr > 512 || (rr >= 256 && scf > 64) || (rr == 512 && scf > 32) ||
                      dev.min_device_interval > send_interval(scf, rr)))
    return fail(kIocrBlock, 11);
  if (udp && (rr < 1 || rr > 16384 || (rr >= 8192 && scf > 64) || (rr == 16384 && scf > 32)))
    return fail(kIocrBlock, 11);
  if (c.phase == 0 || c.phase > rr) return fail(kIocrBlock, 12);
  if (c.frame_send_offset != iocr::kFrameSendOffsetBestEffort &&
      (c.frame_send_offset >= std::uint32_t{scf} * 31250U || c.frame_send_offset >= 0x003D0900U))
    return fail(kIocrBlock, 14);
  // DataHoldFactor 1..0x1E00, and the hold time at most 1.92 s (RT_CLASS_1..3)
  // or 61.44 s (UDP), in p-net's 32-bit arithmetic, which wraps for large
  // products (connect_warnings() reports what that lets through).
  const std::uint32_t hold_us = std::uint32_t{c.data_hold_factor} * rr * scf * 1000U / 32U;
  if (c.data_hold_factor < 1 || c.data_hold_factor > 0x1E00 || (udp && hold_us > 61440000U) ||
      (frame_class && hold_us > 1920000U))
    return fail(kIocrBlock, 16);
  // IOCRTagHeader: p-net reads the VLAN ID as bits 0..10 and wants 0 there,
  // and priority 6.
  if ((c.iocr_tag_header & 0x07FFU) != 0 || (c.iocr_tag_header >> 13) != 6)
    return fail(kIocrBlock, 17);
  if (multicast && (c.multicast_mac[0] & 0x01) == 0) return fail(kIocrBlock, 18);
  if (c.apis.empty()) return fail(kIocrBlock, 19);
  // RT over UDP: p-net wants the initiator MAC all zero (AR 0x07) and the
  // initiator's UDP RT port above 0x03FF (AR 0x0B).
  if (udp && std::any_of(ar.cm_initiator_mac.begin(), ar.cm_initiator_mac.end(),
                         [](std::uint8_t b) { return b != 0; }))
    return fail(kArBlock, 7);
  if (udp && ar.initiator_udp_rt_port <= 0x03FF) return fail(kArBlock, 11);
  // Beyond p-net: a C_SDU above 1440 bytes does not fit a frame (p-net
  // cannot run it either; it checks the length for RT_CLASS_1 and UDP only).
  if (c.data_length > iocr::kMaxCSduLength) return fail(kIocrBlock, 8);
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

const ModuleDescription* device_module(const DeviceDescription& dev, std::uint16_t slot) {
  for (const auto& m : dev.modules)
    if (m.slot == slot) return &m;
  return nullptr;
}
const SubmoduleDescription* device_submodule(const ModuleDescription& m, std::uint16_t subslot) {
  for (const auto& s : m.submodules)
    if (s.subslot == subslot) return &s;
  return nullptr;
}

}  // namespace

std::optional<PnioStatus> check_connect(const ConnectRequest& req, const DeviceDescription& dev) {
  if (auto e = check_ar(req.ar)) return e;
  for (const auto& c : req.iocrs)
    if (auto e = check_iocr(c, req.ar, dev)) return e;
  const auto apis = connect_detail::expected_apis(req);
  if (auto e = connect_detail::check_expected(req, apis, dev)) return e;
  if (auto e = connect_detail::check_iocr_entries(req, apis)) return e;
  const auto count = [&](std::uint16_t type) {
    return std::count_if(req.iocrs.begin(), req.iocrs.end(),
                         [&](const auto& c) { return c.iocr_type == type; });
  };
  if (count(iocr::kTypeInput) == 0 || count(iocr::kTypeOutput) == 0)
    return fail(kCmrpc, connect_error::kCmrpcIocrMissing);
  if (req.alarm_cr_blocks != 1) return fail(kCmrpc, connect_error::kCmrpcWrongBlockCount);
  // RT_CLASS_3 needs an IRInfoBlock, which this device (as a p-net device
  // without one configured) never has.
  if (std::any_of(req.iocrs.begin(), req.iocrs.end(),
                  [](const auto& c) { return rt_class_of(c) == rt_class::kClass3; }))
    return fail(kCmrpc, connect_error::kCmrpcWrongBlockCount);
  if (auto e = check_alarm_cr(req.alarm_cr)) return e;
  // pf_cmdev_check_ar_rpc
  if (req.ar_rpc && req.ar_rpc->initiator_rpc_server_port < 0x0400) return fail(kArRpcBlock, 4);
  return std::nullopt;
}

std::uint16_t output_frame_id(const IocrBlockReq& output, std::uint16_t input_frame_id) {
  if (output.frame_id != 0xFFFF && is_cyclic(output.frame_id) && output.frame_id != input_frame_id)
    return output.frame_id;
  std::uint16_t first = frame_id::kRtClass1First, last = frame_id::kRtClass1Last;
  if (rt_class_of(output) == rt_class::kClass2) {
    first = frame_id::kRtClass2First;
    last = frame_id::kRtClass2Last;
  } else if (rt_class_of(output) == rt_class::kClass3) {
    first = frame_id::kRtClass3First;
    last = frame_id::kRtClass3Last;
  }
  return first != input_frame_id ? first : static_cast<std::uint16_t>(std::min(first + 1, +last));
}

std::optional<ModuleDiffBlock> module_diff(const ConnectRequest& req,
                                           const DeviceDescription& dev) {
  ModuleDiffBlock diff;
  for (const auto& api : connect_detail::expected_apis(req))
    for (const ExpectedModule* m : api.modules) {
      const ModuleDescription* real = device_module(dev, m->slot);
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
          const SubmoduleDescription* rs = device_submodule(*real, s.subslot);
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
      auto it = std::find_if(diff.apis.begin(), diff.apis.end(),
                             [&](const ModuleDiffApi& a) { return a.api == m->api; });
      if (it == diff.apis.end()) it = diff.apis.insert(diff.apis.end(), ModuleDiffApi{m->api, {}});
      it->modules.push_back(std::move(md));
    }
  if (diff.apis.empty()) return std::nullopt;
  return diff;
}

}  // namespace plc::profinet

// The Connect request from a DeviceDescription. Every field a device checks
// (p-net pf_cmdev.c, fieldbus-masters.md §1 item 2) is chosen inside its
// allowed range here, so a Connect we build is never refused for a
// parameter of ours: AR type IOCARSingle, activity timeout 1..1000, our
// valid station name, SendClockFactor a power of two, ReductionRatio 1..512
// with the product >= the device's minimum interval, Phase 1, best-effort
// FrameSendOffset, DataHoldFactor 1..0x1E00, C_SDU 40..1440, input FrameID
// in 0xC000..0xF7FF, AlarmCR LT 0x8892 with timeout factor 1..100, retries
// 3..15 and max alarm data 200..1432.
#include "plc/profinet/controller/connect_plan.hpp"

#include <stdexcept>

namespace plc::profinet {

Uuid controller_object_uuid(const ControllerConfig& cfg) {
  return pnio_object_uuid(1, cfg.device_id, cfg.vendor_id);
}

ConnectPlan plan_connect(const ControllerConfig& cfg, const DeviceDescription& desc,
                         const Mac& controller_mac, const Uuid& ar_uuid, std::uint16_t session_key,
                         std::uint16_t input_frame_id) {
  ConnectPlan p;
  ConnectRequest& r = p.request;
  r.ar.ar_type = ar::kTypeIocarSingle;
  r.ar.ar_uuid = ar_uuid;
  r.ar.session_key = session_key;
  r.ar.cm_initiator_mac = controller_mac;
  r.ar.cm_initiator_object_uuid = controller_object_uuid(cfg);
  r.ar.ar_properties = ar::kPropertiesDefault;
  r.ar.activity_timeout_factor = 600;  // 60 s (x 100 ms), 1..1000
  r.ar.initiator_udp_rt_port = kRpcUdpPort;
  r.ar.station_name = cfg.station_name;

  // One ExpectedSubmoduleBlockReq per module (slot), in slot order.
  for (const ModuleDescription& m : desc.modules) {
    ExpectedSubmoduleBlockReq b;
    // A module's submodules may sit in different APIs (the DAP in API 0,
    // a drive object in 0x3A00): one ExpectedModule per (API, slot).
    for (const SubmoduleDescription& s : m.submodules) {
      if (b.modules.empty() || b.modules.back().api != s.api) {
        ExpectedModule em;
        em.api = s.api;
        em.slot = m.slot;
        em.module_ident = m.module_ident;
        b.modules.push_back(em);
      }
      ExpectedSubmodule es;
      es.subslot = s.subslot;
      es.submodule_ident = s.submodule_ident;
      es.input_length = s.input_length;
      es.output_length = s.output_length;
      b.modules.back().submodules.push_back(es);
    }
    r.expected.push_back(std::move(b));
  }
  if (const WireStatus st = compute_layout(r.expected, p.layout); !st)
    throw std::invalid_argument(std::string("the IO data does not fit one RT_CLASS_1 frame (") +
                                st.reason + ")");

  const std::int64_t clock_ns = std::int64_t{31250} * cfg.send_clock_factor;
  std::uint16_t ratio = cfg.reduction_ratio;
  // The device's minimum interval rules (SendClockFactor x ReductionRatio
  // >= MinDeviceInterval): raise the ratio (a power of two) until it holds.
  while (clock_ns * ratio < desc.min_device_interval.count() && ratio < 512)
    ratio = static_cast<std::uint16_t>(ratio * 2);
  auto iocr = [&](std::uint16_t type, std::uint16_t ref, std::uint16_t frame_id,
                  const IocrLayout& layout) {
    IocrBlockReq b;
    b.iocr_type = type;
    b.iocr_reference = ref;
    b.lt = iocr::kLtProfinet;
    b.iocr_properties = iocr::kPropertiesRtClass1;
    b.frame_id = frame_id;
    b.send_clock_factor = cfg.send_clock_factor;
    b.reduction_ratio = ratio;
    b.phase = 1;
    b.sequence = 0;
    b.frame_send_offset = iocr::kFrameSendOffsetBestEffort;
    b.watchdog_factor = cfg.data_hold_factor;
    b.data_hold_factor = cfg.data_hold_factor;
    b.iocr_tag_header = iocr::kTagHeaderPriority6;
    apply_layout(layout, b);
    return b;
  };
  r.iocrs.push_back(iocr(iocr::kTypeInput, 1, input_frame_id, p.layout.input));
  // The output FrameID is the device's choice (it consumes the frames); we
  // propose the next one, the Connect response says which it took.
  r.iocrs.push_back(
      iocr(iocr::kTypeOutput, 2, static_cast<std::uint16_t>(input_frame_id + 1), p.layout.output));

  r.alarm_cr.alarm_cr_type = alarm_cr::kType;
  r.alarm_cr.lt = iocr::kLtProfinet;
  r.alarm_cr.properties = 0;
  r.alarm_cr.rta_timeout_factor = 1;  // 100 ms
  r.alarm_cr.rta_retries = 3;
  r.alarm_cr.local_alarm_reference = 1;
  r.alarm_cr.max_alarm_data_length = alarm_cr::kDefaultMaxData;

  // The user data of every submodule with IO data, in description order.
  std::size_t in_at = 0, out_at = 0;
  for (const ModuleDescription& m : desc.modules)
    for (const SubmoduleDescription& s : m.submodules) {
      if (s.input_length > 0) {
        const IoDataObject* o = p.layout.input.find(s.api, m.slot, s.subslot);
        if (!o) throw std::invalid_argument("internal: input submodule missing from the layout");
        p.inputs.push_back({*o, in_at});
        in_at += s.input_length;
      }
      if (s.output_length > 0) {
        const IoDataObject* o = p.layout.output.find(s.api, m.slot, s.subslot);
        if (!o) throw std::invalid_argument("internal: output submodule missing from the layout");
        p.outputs.push_back({*o, out_at});
        out_at += s.output_length;
      }
    }
  return p;
}

}  // namespace plc::profinet

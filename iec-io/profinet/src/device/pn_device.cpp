// The PROFINET device stack in front of one DeviceModel (pn_device.hpp).
#include "plc/profinet/device/pn_device.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "plc/profinet/device/connect_check.hpp"
#include "plc/profinet/device/record_status.hpp"
#include "plc/profinet/wire/alarm.hpp"
#include "plc/profinet/wire/blocks.hpp"
#include "plc/profinet/wire/cyclic.hpp"
#include "plc/profinet/wire/dcp.hpp"
#include "plc/profinet/wire/ethernet.hpp"

namespace plc::profinet {

using std::chrono::milliseconds;
using std::chrono::nanoseconds;

namespace {
// A record response header: the addressing fields echoed from the request.
RecordResponseHeader record_response_for(const RecordRequestHeader& h) {
  RecordResponseHeader r;
  r.seq_number = h.seq_number;
  r.ar_uuid = h.ar_uuid;
  r.api = h.api;
  r.slot = h.slot;
  r.subslot = h.subslot;
  r.index = h.index;
  return r;
}
constexpr std::uint16_t kOurAlarmReference = 0x0001;
constexpr int kMaxDatagramsPerPoll = 16;
constexpr int kMaxFramesPerPoll = 256;
constexpr std::size_t kDelayRing = 64;
}  // namespace

const char* to_string(PnDeviceState s) {
  switch (s) {
    case PnDeviceState::Idle:
      return "idle";
    case PnDeviceState::Parameterizing:
      return "parameterizing";
    case PnDeviceState::AppReady:
      return "application ready";
    case PnDeviceState::DataExchange:
      return "data exchange";
  }
  return "?";
}

const char* to_string(ArEnd e) {
  switch (e) {
    case ArEnd::Released:
      return "released";
    case ArEnd::DataHoldExpired:
      return "data hold expired";
    case ArEnd::StartupTimeout:
      return "start-up timeout";
    case ArEnd::AlarmTimeout:
      return "alarm not acknowledged";
    case ArEnd::AppReadyTimeout:
      return "ApplicationReady not answered";
    case ArEnd::Aborted:
      return "aborted by the controller";
  }
  return "?";
}

std::string describe(const PnDeviceEvent& e) {
  char buf[64];
  switch (e.kind) {
    case PnDeviceEvent::Kind::Connected:
      return "connected";
    case PnDeviceEvent::Kind::Refused:
      std::snprintf(buf, sizeof buf, "refused %08X", static_cast<unsigned>(e.status.value()));
      return buf;
    case PnDeviceEvent::Kind::DataExchange:
      return "data exchange";
    case PnDeviceEvent::Kind::Lost:
      return std::string("lost (") + to_string(e.end) + ")";
    case PnDeviceEvent::Kind::Released:
      return "released";
    case PnDeviceEvent::Kind::AlarmAcked:
      return "alarm acknowledged";
    case PnDeviceEvent::Kind::NameSet:
      return "name set";
    case PnDeviceEvent::Kind::IpSet:
      return "ip set";
    case PnDeviceEvent::Kind::Warning:
      return "warning: " + e.text;
  }
  return "?";
}

// One alarm channel (high or low priority) of the RTA protocol.
struct AlarmChannel {
  bool high = false;
  std::uint16_t send_seq = rta::kSeqInitial;  // last DATA we sent
  std::uint16_t rx_seq = rta::kSeqInitial;    // last DATA we received
  bool pending = false;                       // a notification not yet acknowledged (AlarmAck)
  bool transport_acked = false;               // its ACK-RTA came
  int retries_left = 0;
  nanoseconds next_retry{0};
  std::vector<std::uint8_t> frame;  // the notification, for repeats
  std::uint16_t specifier = 0;
};

struct PnDevice::Ar {
  ConnectRequest req;
  Mac controller_mac{};
  Ipv4 controller_ip;
  IocrLayout in_layout, out_layout;
  std::uint16_t in_frame_id = 0, out_frame_id = 0;
  nanoseconds interval{milliseconds(1)};   // our input frames
  nanoseconds data_hold{milliseconds(3)};  // controller's output frames
  std::uint16_t counter_step = 32;
  std::uint16_t cycle_counter = 0;
  nanoseconds next_send{0};
  nanoseconds last_valid{-1};
  nanoseconds startup_deadline{0};
  std::vector<std::uint8_t> in_iops;  // per input data object
  std::vector<std::uint8_t> in_iocs;  // per input IOCS slot
  // Our input frame in tx_, built once per AR (build_cyclic_frame()): its
  // length (0: it cannot be built), where the model's inputs go in it.
  bool tx_built = false;
  std::size_t tx_length = 0;
  std::size_t model_in_at = 0, model_in_bytes = 0;
  int model_in = -1, model_out = -1;  // index into the layouts' data objects
  bool model_out_proper = false;
  bool app_ready_done = false, got_output = false;
  int app_ready_left = 0;
  nanoseconds app_ready_next{0};
  std::vector<std::uint8_t> app_ready_datagram;
  Uuid app_ready_activity;
  AlarmChannel alarm_low, alarm_high;
  std::uint16_t alarm_sequence = 0;  // AlarmSpecifier.SequenceNumber
  std::vector<std::uint8_t> connect_response;
};

PnDevice::PnDevice(PnDeviceConfig cfg, std::unique_ptr<io::DeviceModel> model, EthernetPort& eth,
                   UdpOpener open_udp)
    : cfg_(std::move(cfg)), model_(std::move(model)), eth_(eth), open_udp_(std::move(open_udp)) {
  if (!model_) throw std::invalid_argument("PnDevice: no device model");
  const SubmoduleDescription* io = cfg_.description.io_submodule();
  if (!io) throw std::invalid_argument("PnDevice: the description has no modules");
  if (io->input_length != model_->input_size() || io->output_length != model_->output_size())
    throw std::invalid_argument(
        "PnDevice: the IO submodule's lengths (" + std::to_string(io->input_length) + "/" +
        std::to_string(io->output_length) + ") differ from the model's (" +
        std::to_string(model_->input_size()) + "/" + std::to_string(model_->output_size()) + ")");
  station_name_ = cfg_.description.station_name;
  ip_ = cfg_.description.ip;
  netmask_ = cfg_.description.netmask;
  gateway_ = cfg_.description.gateway;
  mac_ = cfg_.mac ? *cfg_.mac : eth_.mac();
  eth_queued_ = eth_.queued_count();
  from_plc_.assign(model_->output_size(), 0);
  to_plc_.assign(model_->input_size(), 0);
  udp_rx_.resize(kMaxDatagram);
  // Opened here, so that a missing address is an error of the host's set-up
  // (pndevsim: exit 2 with the reason), not of a poll.
  set_udp(open_udp_(ip_));
  delayed_.resize(kDelayRing);
}

PnDevice::~PnDevice() = default;

void PnDevice::set_udp(std::unique_ptr<UdpPort> port) {
  udp_ = std::move(port);
  udp_queued_ = udp_ ? udp_->queued_count() : nullptr;
}

void PnDevice::emit(PnDeviceEvent e) {
  if (sink_) sink_(e);
}

void PnDevice::send_eth(std::span<const std::uint8_t> frame) {
  if (!quiet()) (void)eth_.send(frame);
}

void PnDevice::send_udp(Ipv4 ip, std::uint16_t port, std::span<const std::uint8_t> d) {
  if (udp_ && !quiet()) (void)udp_->send_to(ip, port, d);
}

// ---------------------------------------------------------------- poll

void PnDevice::poll(nanoseconds now) {
  now_ = now;
  if (!started_) {
    started_ = true;
    last_step_ = now;
    next_idle_step_ = now;
    if (cfg_.hello_at_start) send_eth(encode_dcp_hello(mac_, 1, identity()));
  }
  if (!shared_port_) read_ethernet(now);
  if (may_hold(udp_queued_)) read_udp(now);  // mostly nothing there: no call
  timers(now);
  if (ar_) {
    send_cyclic(now);
  } else if (now >= next_idle_step_) {
    std::fill(from_plc_.begin(), from_plc_.end(), 0);
    step_model(now);
    next_idle_step_ = now + cfg_.idle_step;
  }
  flush_delayed(now);
  for (auto it = dcp_out_.begin(); it != dcp_out_.end();) {
    if (now >= it->due) {
      send_eth(it->frame);
      ++counters_.dcp_answers;
      it = dcp_out_.erase(it);
    } else {
      ++it;
    }
  }
}

// Inline in poll(), its one caller: no call per poll.
[[gnu::always_inline]] inline void PnDevice::read_ethernet(nanoseconds now) {
  // Each frame read where the port holds it (the memory hub's buffer: no
  // copy), valid until the next receive.
  for (int i = 0; i < kMaxFramesPerPoll && may_hold(eth_queued_); ++i) {
    const std::span<const std::uint8_t> frame = eth_.receive_view(rx_, nanoseconds(0));
    if (frame.empty()) break;
    take_frame(frame, now);
  }
}

void PnDevice::read_udp(nanoseconds now) {
  if (!udp_) return;
  for (int i = 0; i < kMaxDatagramsPerPoll && may_hold(udp_queued_); ++i) {
    Ipv4 from;
    std::uint16_t port = 0;
    const std::size_t n = udp_->receive_from(udp_rx_, from, port, nanoseconds(0));
    if (n == 0) break;
    if (quiet()) continue;  // a pulled plug hears nothing
    on_rpc(std::span<const std::uint8_t>(udp_rx_.data(), n), from, port, now);
  }
}

void PnDevice::on_frame(std::span<const std::uint8_t> frame, nanoseconds now) {
  take_frame(frame, now);
}

// Inline in read_ethernet() (every frame of a device with its own port; a
// shared port's host, pndevsim, calls on_frame()).
[[gnu::always_inline]] inline void PnDevice::take_frame(std::span<const std::uint8_t> frame,
                                                        nanoseconds now) {
  if (quiet()) return;
  PnFrameView v;
  if (!decode_pn_frame(frame, v)) {
    ++counters_.frames_bad;
    return;
  }
  const bool to_us = v.dst == mac_;
  if (is_dcp(v.frame_id)) {
    if (to_us || v.dst == kDcpIdentifyMulticast) on_dcp(v.frame_id, v.src, v.pdu, now);
    return;
  }
  if (!to_us) return;  // another station's traffic on a shared segment
  ++counters_.frames_received;
  if (is_alarm(v.frame_id)) {
    on_alarm(v.frame_id, v.src, v.pdu, now);
  } else if (ar_ && v.frame_id == ar_->out_frame_id) {
    on_cyclic(frame, v, now);
  } else {
    ++counters_.frames_unknown;
  }
}

// ---------------------------------------------------------------- DCP

DcpIdentity PnDevice::identity() const {
  DcpIdentity id;
  id.station_name = station_name_;
  id.type_of_station = "softplc pndevsim";
  id.vendor_id = cfg_.description.vendor_id;
  id.device_id = cfg_.description.device_id;
  id.device_role = dcp::kRoleDevice;
  id.ip = {ip_.host_order, netmask_.host_order, gateway_.host_order};
  id.device_instance = cfg_.description.instance;
  return id;
}

// (MAC mod ResponseDelayFactor) x 10 ms, the MAC's last two bytes as the
// number (IEC 61158-6-10 DCP "ResponseDelay"; fieldbus-masters.md §1 item 1).
nanoseconds dcp_response_delay(const Mac& mac, std::uint16_t factor) {
  if (factor <= 1) return nanoseconds(0);
  const unsigned v = (unsigned{mac[4]} << 8) | mac[5];
  return milliseconds(10) * static_cast<int>(v % factor);
}

void PnDevice::on_dcp(std::uint16_t frame_id, const Mac& src, std::span<const std::uint8_t> pdu,
                      nanoseconds now) {
  DcpMessage m;
  if (!decode_dcp(frame_id, pdu, m)) {
    ++counters_.frames_bad;
    return;
  }
  if (m.service_type != dcp::kTypeRequest) return;  // other devices' answers
  ++counters_.dcp_requests;
  if (frame_id == frame_id::kDcpIdentifyRequest && m.service_id == dcp::kServiceIdentify) {
    const auto filter = identify_filter(m);
    if (filter && *filter != station_name_) return;
    dcp_out_.push_back({now + dcp_response_delay(mac_, m.response_delay),
                        encode_dcp_identify_response(src, mac_, m.xid, identity())});
    return;
  }
  if (frame_id != frame_id::kDcpGetSet) return;
  if (m.service_id == dcp::kServiceGet) {
    std::vector<std::pair<std::uint8_t, std::uint8_t>> opts;
    for (const auto& b : m.blocks) opts.emplace_back(b.option, b.suboption);
    send_eth(encode_dcp_get_response(src, mac_, m.xid, identity(), opts));
    ++counters_.dcp_answers;
  } else if (m.service_id == dcp::kServiceSet) {
    DcpSetRequest req;
    std::vector<DcpSetResult> results;
    if (!set_request_from(m, req)) {
      for (const auto& b : m.blocks)
        results.push_back({b.option, b.suboption, dcp::kErrorSuboptionUnsupported});
    } else {
      // Our reading: name and address stay fixed while an AR is up (p-net
      // would abort the AR); the controller names devices before Connect.
      const bool locked = ar_ != nullptr;
      if (req.station_name) {
        const bool ok =
            !locked && (req.station_name->empty() || valid_station_name(*req.station_name));
        results.push_back({dcp::kOptDevice, dcp::kSubDeviceNameOfStation,
                           ok ? dcp::kErrorOk : dcp::kErrorSetNotPossible});
        if (ok) {
          station_name_ = *req.station_name;
          emit({PnDeviceEvent::Kind::NameSet});
        }
      }
      if (req.ip) {
        bool ok = !locked;
        if (ok && req.ip->ip != ip_.host_order) {
          try {
            set_udp(nullptr);  // unbind first: a Memory network allows one owner per ip:port
            set_udp(open_udp_(Ipv4{req.ip->ip}));
          } catch (const std::exception&) {
            ok = false;
            try {
              set_udp(open_udp_(ip_));
            } catch (const std::exception&) {
              set_udp(nullptr);  // no RPC until the next successful Set IP
            }
          }
        }
        results.push_back(
            {dcp::kOptIp, dcp::kSubIpParameter, ok ? dcp::kErrorOk : dcp::kErrorSetNotPossible});
        if (ok) {
          ip_ = Ipv4{req.ip->ip};
          netmask_ = Ipv4{req.ip->netmask};
          gateway_ = Ipv4{req.ip->gateway};
          emit({PnDeviceEvent::Kind::IpSet});
        }
      }
      if (req.signal) results.push_back({dcp::kOptControl, dcp::kSubControlSignal, dcp::kErrorOk});
      if (req.reset_factory)
        results.push_back({dcp::kOptControl, dcp::kSubControlResetToFactory, dcp::kErrorOk});
    }
    send_eth(encode_dcp_set_response(src, mac_, m.xid, results));
    ++counters_.dcp_answers;
  }
}

// ---------------------------------------------------------------- RPC

void PnDevice::on_rpc(std::span<const std::uint8_t> dgram, Ipv4 from, std::uint16_t port,
                      nanoseconds now) {
  RpcPdu pdu;
  if (!decode_rpc(dgram, pdu)) {
    ++counters_.rpc_bad;
    return;
  }
  const RpcHeader& h = pdu.header;
  if (h.packet_type == rpc::kResponse) {
    on_app_ready_response(pdu, now);
    return;
  }
  if (h.packet_type != rpc::kRequest || h.interface != kPnioDeviceInterface) {
    ++counters_.rpc_bad;
    return;
  }
  ++counters_.rpc_requests;
  // A repeated request (same activity and sequence): the same answer again,
  // without doing the work twice.
  if (!last_response_.empty() && h.activity == last_activity_ && h.sequence_number == last_seq_) {
    send_udp(from, port, last_response_);
    return;
  }
  NdrRequest ndr;
  PnioStatus status;
  std::vector<std::uint8_t>& args = rpc_args_;
  args.clear();  // empty unless the service answers with args
  if (!decode_ndr_request(pdu.body, h.little_endian, ndr)) {
    ++counters_.rpc_bad;
    status = connect_refusal(connect_error::kCmrpc, connect_error::kCmrpcArgsLengthInvalid);
  } else {
    switch (h.opnum) {
      case rpc::kOpConnect:
        status = serve_connect(ndr.args, from, args, now);
        break;
      case rpc::kOpRelease:
        status = serve_release(ndr.args, args, now);
        break;
      case rpc::kOpRead:
      case rpc::kOpReadImplicit:
        status = serve_read(ndr.args, h.opnum, args);
        break;
      case rpc::kOpWrite:
        status = serve_write(ndr.args, args);
        break;
      case rpc::kOpControl:
        status = serve_control(ndr.args, args, now);
        break;
      default:
        ++counters_.rpc_bad;
        status = connect_refusal(connect_error::kCmrpc, connect_error::kCmrpcUnknownBlocks);
        break;
    }
  }
  encode_ndr_response_to(rpc_body_, status, ndr.args_maximum, args, h.little_endian);
  encode_rpc_to(last_response_, response_header_for(h), rpc_body_);
  last_activity_ = h.activity;
  last_seq_ = h.sequence_number;
  send_udp(from, port, last_response_);
}

PnioStatus PnDevice::serve_connect(std::span<const std::uint8_t> args, Ipv4 from,
                                   std::vector<std::uint8_t>& out, nanoseconds now) {
  ++counters_.connects;
  ConnectRequest req;
  std::optional<PnioStatus> unreadable = check_connect_blocks(args);
  if (!unreadable && !decode_connect_request(args, req))
    unreadable = connect_refusal(connect_error::kCmrpc, connect_error::kCmrpcUnknownBlocks);
  if (unreadable) {
    ++counters_.connects_refused;
    emit({PnDeviceEvent::Kind::Refused, *unreadable});
    return *unreadable;
  }
  if (ar_ && ar_->req.ar.ar_uuid == req.ar.ar_uuid) {  // the answer got lost: same again
    out = ar_->connect_response;
    return {};
  }
  std::optional<PnioStatus> refusal = faults_.refuse_connect;
  if (!refusal && ar_)
    refusal = connect_refusal(connect_error::kCmrpc, connect_error::kCmrpcNoArResources);
  if (!refusal) refusal = check_connect(req, cfg_.description);
  auto ar = std::make_unique<Ar>();
  if (!refusal) refusal = setup_ar(req, *ar);
  if (refusal) {
    ++counters_.connects_refused;
    emit({PnDeviceEvent::Kind::Refused, *refusal});
    return *refusal;
  }
  ar->req = std::move(req);
  ar->controller_mac = ar->req.ar.cm_initiator_mac;
  ar->controller_ip = from;
  ar->next_send = now;  // output frames right after the Connect response
  ar->startup_deadline = now + milliseconds(100) * ar->req.ar.activity_timeout_factor;

  ConnectResponse res;
  res.ar.ar_type = ar->req.ar.ar_type;
  res.ar.ar_uuid = ar->req.ar.ar_uuid;
  res.ar.session_key = ar->req.ar.session_key;
  res.ar.cm_responder_mac = mac_;
  res.ar.responder_udp_rt_port = kRpcUdpPort;
  for (const auto& c : ar->req.iocrs)
    res.iocrs.push_back({c.iocr_type, c.iocr_reference,
                         c.iocr_type == iocr::kTypeInput ? ar->in_frame_id : ar->out_frame_id});
  res.alarm_cr.alarm_cr_type = ar->req.alarm_cr.alarm_cr_type;
  res.alarm_cr.local_alarm_reference = kOurAlarmReference;
  res.alarm_cr.max_alarm_data_length = ar->req.alarm_cr.max_alarm_data_length;
  res.module_diff = module_diff(ar->req, cfg_.description);
  res.ar_server = ArServerBlock{station_name_};
  ar->connect_response = encode_connect_response(res);
  out = ar->connect_response;

  accept_.start(ar->controller_mac, cyclic_frame_length(ar->out_layout.c_sdu_length, false));
  std::fill(from_plc_.begin(), from_plc_.end(), 0);
  ar_ = std::move(ar);
  state_ = PnDeviceState::Parameterizing;
  emit({PnDeviceEvent::Kind::Connected});
  for (auto& w : connect_warnings(ar_->req)) {
    PnDeviceEvent e{PnDeviceEvent::Kind::Warning};
    e.text = std::move(w);
    emit(e);
  }
  return {};
}

// Layouts, frame IDs, timing and per-submodule status of an accepted
// Connect. check_connect() has refused every layout the wire codec cannot
// build; should one get through, it is refused like p-net's IOCR overlap
// check (IOCR block, 24).
std::optional<PnioStatus> PnDevice::setup_ar(const ConnectRequest& req, Ar& ar) {
  const IocrBlockReq* in = nullptr;
  const IocrBlockReq* out = nullptr;
  for (const auto& c : req.iocrs) {
    if (c.iocr_type == iocr::kTypeInput) in = &c;
    if (c.iocr_type == iocr::kTypeOutput) out = &c;
  }
  if (!in || !out || !layout_from_iocr(*in, req.expected, ar.in_layout) ||
      !layout_from_iocr(*out, req.expected, ar.out_layout))
    return connect_refusal(connect_error::kIocrBlock, 24);
  ar.in_frame_id = in->frame_id;
  // The consumer picks the output FrameID (p-net's rule, connect_check.hpp).
  ar.out_frame_id = output_frame_id(*out, in->frame_id);
  ar.interval = send_interval(in->send_clock_factor, in->reduction_ratio);
  ar.counter_step = static_cast<std::uint16_t>(in->send_clock_factor * in->reduction_ratio);
  ar.data_hold =
      send_interval(out->send_clock_factor, out->reduction_ratio) * out->data_hold_factor;

  // Which expected submodules match ours (ident and lengths): those get
  // IOPS/IOCS good, the others bad (they are in the ModuleDiffBlock).
  const SubmoduleDescription* io = cfg_.description.io_submodule();
  const ModuleDescription* io_mod = cfg_.description.module_of(io);
  auto proper = [&](std::uint32_t api, std::uint16_t slot, std::uint16_t subslot) {
    for (const auto& b : req.expected)
      for (const auto& m : b.modules) {
        if (m.api != api || m.slot != slot) continue;
        for (const auto& mod : cfg_.description.modules) {
          if (mod.slot != slot) continue;
          if (mod.module_ident != m.module_ident) return false;
          for (const auto& s : m.submodules) {
            if (s.subslot != subslot) continue;
            for (const auto& real : mod.submodules)
              if (real.subslot == subslot)
                return real.submodule_ident == s.submodule_ident && real.api == api &&
                       real.input_length == s.input_length && real.output_length == s.output_length;
          }
        }
      }
    return false;
  };
  for (std::size_t i = 0; i < ar.in_layout.data.size(); ++i) {
    const auto& d = ar.in_layout.data[i];
    const bool ok = proper(d.api, d.slot, d.subslot);
    ar.in_iops.push_back(ok ? iocr::kIoxsGood : iocr::kIoxsBad);
    if (ok && d.slot == io_mod->slot && d.subslot == io->subslot && d.api == io->api)
      ar.model_in = static_cast<int>(i);
  }
  for (const auto& c : ar.in_layout.iocs)
    ar.in_iocs.push_back(proper(c.api, c.slot, c.subslot) ? iocr::kIoxsGood : iocr::kIoxsBad);
  for (std::size_t i = 0; i < ar.out_layout.data.size(); ++i) {
    const auto& d = ar.out_layout.data[i];
    if (d.slot == io_mod->slot && d.subslot == io->subslot && d.api == io->api) {
      ar.model_out = static_cast<int>(i);
      ar.model_out_proper = proper(d.api, d.slot, d.subslot);
    }
  }
  return std::nullopt;
}

bool PnDevice::ar_matches(const Uuid& ar_uuid) const {
  return ar_ && ar_->req.ar.ar_uuid == ar_uuid;
}

PnioStatus PnDevice::serve_release(std::span<const std::uint8_t> args,
                                   std::vector<std::uint8_t>& out, nanoseconds now) {
  ControlBlock c;
  if (!decode_control(args, c) || c.block_type != block::kReleaseReq)
    return {pnio_error::kCodeRelease, pnio_error::kDecodePnio, 0x28, 0};  // RELS faulty block
  if (!ar_matches(c.ar_uuid))
    return {pnio_error::kCodeRelease, pnio_error::kDecodePnio, connect_error::kCmrpc,
            connect_error::kCmrpcArUuidUnknown};
  out = encode_control(control_response_for(c));
  ++counters_.releases;
  end_ar(ArEnd::Released, now);
  return {};
}

PnioStatus PnDevice::serve_control(std::span<const std::uint8_t> args,
                                   std::vector<std::uint8_t>& out, nanoseconds now) {
  ControlBlock c;
  if (!decode_control(args, c) || c.block_type != block::kPrmEndReq ||
      c.command != control::kPrmEnd)
    return {pnio_error::kCodeControl, pnio_error::kDecodePnio, 0x14,
            0x08};  // DCTRL: ControlCommand
  if (!ar_matches(c.ar_uuid) || c.session_key != ar_->req.ar.session_key)
    return {pnio_error::kCodeControl, pnio_error::kDecodePnio, connect_error::kCmrpc,
            connect_error::kCmrpcArUuidUnknown};
  if (state_ != PnDeviceState::Parameterizing)
    return {pnio_error::kCodeControl, pnio_error::kDecodePnio, connect_error::kCmrpc,
            connect_error::kCmrpcStateConflict};
  out = encode_control(control_response_for(c));
  // ApplicationReady to the controller's RPC server (UDP 34964), object =
  // its CMInitiatorObjectUUID; repeated until it answers DONE.
  Ar& ar = *ar_;
  ControlBlock ready;
  ready.block_type = block::kApplicationReadyReq;
  ready.ar_uuid = ar.req.ar.ar_uuid;
  ready.session_key = ar.req.ar.session_key;
  ready.command = control::kApplicationReady;
  RpcHeader h;
  h.packet_type = rpc::kRequest;
  h.object = ar.req.ar.cm_initiator_object_uuid;
  h.interface = kPnioControllerInterface;
  // A fresh activity per AR, derived from the AR UUID (reproducible runs).
  ar.app_ready_activity = ar.req.ar.ar_uuid;
  ar.app_ready_activity.data1 ^= 0x00A9A9A9U;
  h.activity = ar.app_ready_activity;
  h.opnum = rpc::kOpControl;
  h.sequence_number = 0;
  ar.app_ready_datagram =
      encode_rpc(h, encode_ndr_request(rpc::kMaxArgs, encode_control(ready), h.little_endian));
  ar.app_ready_left = cfg_.app_ready_retries;
  ar.app_ready_next = now;  // sent from timers(), after this response
  state_ = PnDeviceState::AppReady;
  return {};
}

void PnDevice::on_app_ready_response(const RpcPdu& pdu, nanoseconds now) {
  if (!ar_ || state_ != PnDeviceState::AppReady || pdu.header.activity != ar_->app_ready_activity)
    return;
  NdrResponse ndr;
  ControlBlock c;
  if (!decode_ndr_response(pdu.body, pdu.header.little_endian, ndr) || !ndr.status.ok() ||
      !decode_control(ndr.args, c) || c.block_type != block::kApplicationReadyRes ||
      c.command != control::kDone || c.ar_uuid != ar_->req.ar.ar_uuid) {
    ++counters_.rpc_bad;
    return;
  }
  ar_->app_ready_done = true;
  maybe_enter_data_exchange(now);
}

void PnDevice::maybe_enter_data_exchange(nanoseconds) {
  if (ar_ && state_ == PnDeviceState::AppReady && ar_->app_ready_done && ar_->got_output) {
    state_ = PnDeviceState::DataExchange;
    emit({PnDeviceEvent::Kind::DataExchange});
  }
}

// The records of the device's slots go to the model; one record space for
// all of them, as the sim plugin has it.
bool PnDevice::has_subslot(std::uint32_t api, std::uint16_t slot, std::uint16_t subslot) const {
  for (const auto& m : cfg_.description.modules)
    if (m.slot == slot)
      for (const auto& s : m.submodules)
        if (s.subslot == subslot && (s.api == api || slot == 0)) return true;
  return false;
}

PnioStatus PnDevice::write_one(const RecordRequestHeader& h, std::span<const std::uint8_t> data) {
  ++counters_.writes;
  if (!has_subslot(h.api, h.slot, h.subslot)) {
    ++counters_.record_errors;
    return invalid_slot_status(true);
  }
  const io::RecordError e = model_->write_record(h.index, data);
  if (e != io::RecordError::None) ++counters_.record_errors;
  return record_status(e, true);
}

PnioStatus PnDevice::serve_write(std::span<const std::uint8_t> args,
                                 std::vector<std::uint8_t>& out) {
  WriteRequest req;
  if (!decode_write_request(args, req))
    return {pnio_error::kCodeWrite, pnio_error::kDecodePnioRw, 0xB8, 0};  // invalid parameter
  if (!ar_matches(req.header.ar_uuid))
    return {pnio_error::kCodeWrite, pnio_error::kDecodePnio, connect_error::kCmrpc,
            connect_error::kCmrpcArUuidUnknown};
  WriteResponse res;
  auto result_for = [](const RecordRequestHeader& h, const PnioStatus& s) {
    RecordResponseHeader r = record_response_for(h);
    r.record_data_length = s.ok() ? h.record_data_length : 0;
    r.status = s;
    return r;
  };
  PnioStatus first_error;
  if (req.multiple()) {
    for (std::size_t i = 0; i < req.sub_headers.size(); ++i) {
      const PnioStatus s = write_one(req.sub_headers[i], req.sub_data[i]);
      if (!s.ok() && first_error.ok()) first_error = s;
      res.sub_results.push_back(result_for(req.sub_headers[i], s));
    }
  } else {
    first_error = write_one(req.header, req.data);
  }
  // Our reading for MultipleWrite: each record's own status in its result;
  // the outer header and the NDR status carry the first failure.
  res.header = result_for(req.header, first_error);
  encode_write_response_to(out, res);
  return first_error;
}

PnioStatus PnDevice::serve_read(std::span<const std::uint8_t> args, std::uint16_t opnum,
                                std::vector<std::uint8_t>& out) {
  ++counters_.reads;
  RecordRequestHeader h;
  if (!decode_read_request(args, h))
    return {pnio_error::kCodeRead, pnio_error::kDecodePnioRw, 0xB8, 0};
  if (opnum == rpc::kOpRead && !ar_matches(h.ar_uuid))
    return {pnio_error::kCodeRead, pnio_error::kDecodePnio, connect_error::kCmrpc,
            connect_error::kCmrpcArUuidUnknown};
  RecordResponseHeader r = record_response_for(h);
  PnioStatus s;
  std::array<std::uint8_t, io::kRecordMaxBytes> buf{};
  std::size_t len = 0;
  if (!has_subslot(h.api, h.slot, h.subslot)) {
    s = invalid_slot_status(false);
  } else {
    const io::RecordError e = model_->read_record(h.index, buf, len);
    s = record_status(e, false);
    if (e == io::RecordError::None && len > h.record_data_length) len = h.record_data_length;
  }
  if (!s.ok()) {
    ++counters_.record_errors;
    len = 0;
  }
  r.record_data_length = static_cast<std::uint32_t>(len);
  encode_read_response_to(out, r, std::span<const std::uint8_t>(buf.data(), len));
  return s;
}

// ---------------------------------------------------------------- cyclic

// Inline in take_frame() (its one caller, itself inline in read_ethernet()):
// no call and no second register save per output frame.
[[gnu::always_inline]] inline void PnDevice::on_cyclic(std::span<const std::uint8_t> frame,
                                                       const PnFrameView& v, nanoseconds now) {
  Ar& ar = *ar_;
  OutputFrameFacts f;
  f.source = v.src;
  f.length_without_vlan = frame.size() - (v.vlan_tci ? kVlanTagLength : 0);
  CyclicView cv;
  const bool decoded = static_cast<bool>(decode_cyclic(v, ar.out_layout.c_sdu_length, cv));
  if (decoded) {
    f.cycle_counter = cv.header.cycle_counter;
    f.data_status = cv.header.data_status;
    f.transfer_status = cv.header.transfer_status;
  }
  if (accept_.check(f)) return;  // dropped, counted by reason
  if (!decoded) return;          // cannot happen once the length is right
  ar.last_valid = now;
  if (ar.model_out >= 0) {
    const IoDataObject& o = ar.out_layout.data[static_cast<std::size_t>(ar.model_out)];
    // Outputs with IOPS bad (or a wrong submodule) reach the model as the
    // substitute value zero.
    if (ar.model_out_proper && (iops(cv.c_sdu, o) & iocr::kIoxsGood)) {
      const auto d = io_data(cv.c_sdu, o);
      copy_io_bytes(from_plc_.data(), d.data(), std::min(d.size(), from_plc_.size()));
    } else {
      std::fill(from_plc_.begin(), from_plc_.end(), 0);
    }
  }
  if (!ar.got_output) {
    ar.got_output = true;
    maybe_enter_data_exchange(now);
  }
}

void PnDevice::step_model(nanoseconds now) {
  const nanoseconds dt = now - last_step_;
  model_->step(now, dt, from_plc_, to_plc_);
  last_step_ = now;
}

// The frame's fixed part, the same for every frame of the AR: header and
// FrameID, zeros, each data object's IOPS and each IOCS; and where the
// model's inputs go.
void PnDevice::build_cyclic_frame(Ar& ar) {
  ar.tx_built = true;
  const std::size_t length = ar.in_layout.c_sdu_length;
  const std::span<std::uint8_t> c_sdu = cyclic_c_sdu(tx_, length, cfg_.vlan_tag);
  std::fill(c_sdu.begin(), c_sdu.end(), std::uint8_t{0});
  // Each data object: the model's inputs in its own (the rest, and every
  // other one, stay zero), then its IOPS.
  for (std::size_t i = 0; i < ar.in_layout.data.size(); ++i) {
    const IoDataObject& o = ar.in_layout.data[i];
    if (std::size_t{o.offset} + o.length + 1 > c_sdu.size()) continue;
    if (static_cast<int>(i) == ar.model_in && !to_plc_.empty()) {
      ar.model_in_at = static_cast<std::size_t>(c_sdu.data() - tx_.data()) + o.offset;
      ar.model_in_bytes = std::min<std::size_t>(to_plc_.size(), o.length);
    }
    c_sdu[o.iops_offset()] = ar.in_iops[i];
  }
  for (std::size_t i = 0; i < ar.in_layout.iocs.size() && !c_sdu.empty(); ++i)
    c_sdu[ar.in_layout.iocs[i].offset] = ar.in_iocs[i];
  CyclicHeader h;
  h.dst = ar.controller_mac;
  h.src = mac_;
  h.frame_id = ar.in_frame_id;
  if (cfg_.vlan_tag) h.vlan_tci = kVlanTciPriority6;
  ar.tx_length = finish_cyclic(tx_, h, length);
}

// Inline in poll(), its one caller: one call less per input frame.
[[gnu::always_inline]] inline void PnDevice::send_cyclic(nanoseconds now) {
  Ar& ar = *ar_;
  if (now < ar.next_send) return;
  step_model(now);
  if (!ar.tx_built) build_cyclic_frame(ar);
  // From frame to frame only the model's inputs and the APDU status change.
  if (ar.model_in_bytes > 0)
    copy_io_bytes(tx_.data() + ar.model_in_at, to_plc_.data(), ar.model_in_bytes);
  ar.cycle_counter = static_cast<std::uint16_t>(ar.cycle_counter + ar.counter_step);
  const std::size_t n = ar.tx_length > 0
                            ? put_cyclic_status(tx_, ar.in_layout.c_sdu_length, cfg_.vlan_tag,
                                                ar.cycle_counter, data_status::kGood, 0)
                            : 0;
  // Never burst: a late poll sends one frame and resumes the grid.
  ar.next_send += ar.interval;
  if (ar.next_send <= now) ar.next_send = now + ar.interval;
  if (n == 0 || quiet()) return;
  if (faults_.drop_all_cyclic || faults_.drop_cyclic > 0) {
    if (faults_.drop_cyclic > 0) --faults_.drop_cyclic;
    ++counters_.frames_dropped_by_fault;
    return;
  }
  if (faults_.delay_cyclic.count() > 0) {
    Delayed& d = delayed_[delayed_tail_ % kDelayRing];
    if (delayed_tail_ - delayed_head_ >= kDelayRing) {
      ++counters_.frames_dropped_by_fault;  // ring full: the oldest is lost
      ++delayed_head_;
    }
    std::copy_n(tx_.begin(), n, d.frame.begin());
    d.length = n;
    d.due = now + faults_.delay_cyclic;
    ++delayed_tail_;
    return;
  }
  (void)eth_.send(std::span<const std::uint8_t>(tx_.data(), n));  // not quiet(): asked above
  ++counters_.frames_sent;
}

void PnDevice::flush_delayed(nanoseconds now) {
  while (delayed_head_ != delayed_tail_) {
    Delayed& d = delayed_[delayed_head_ % kDelayRing];
    if (now < d.due) break;
    send_eth(std::span<const std::uint8_t>(d.frame.data(), d.length));
    ++counters_.frames_sent;
    ++delayed_head_;
  }
}

// ---------------------------------------------------------------- timers

void PnDevice::timers(nanoseconds now) {
  if (!ar_) return;
  const Ar& ar = *ar_;
  // In data exchange with no alarm out and the data hold not expired,
  // none of the timers below acts: no call (once per poll).
  if (state_ == PnDeviceState::DataExchange && !ar.alarm_low.pending && !ar.alarm_high.pending &&
      !(ar.last_valid.count() >= 0 && now - ar.last_valid > ar.data_hold))
    return;
  timers_due(now);
}

void PnDevice::timers_due(nanoseconds now) {
  Ar& ar = *ar_;
  if (ar.last_valid.count() >= 0 && now - ar.last_valid > ar.data_hold) {
    ++counters_.data_hold_expired;
    end_ar(ArEnd::DataHoldExpired, now);
    return;
  }
  if (state_ != PnDeviceState::DataExchange && now > ar.startup_deadline) {
    end_ar(ArEnd::StartupTimeout, now);
    return;
  }
  if (state_ == PnDeviceState::AppReady && !ar.app_ready_done && now >= ar.app_ready_next) {
    if (ar.app_ready_left-- <= 0) {
      end_ar(ArEnd::AppReadyTimeout, now);
      return;
    }
    send_udp(ar.controller_ip, kRpcUdpPort, ar.app_ready_datagram);
    ++counters_.app_ready_sent;
    ar.app_ready_next = now + cfg_.app_ready_retry;
  }
  for (AlarmChannel* ch : {&ar.alarm_low, &ar.alarm_high}) {
    if (!ch->pending || ch->transport_acked || now < ch->next_retry) continue;
    if (ch->retries_left-- <= 0) {
      end_ar(ArEnd::AlarmTimeout, now);
      return;
    }
    send_eth(ch->frame);
    ++counters_.alarm_repeats;
    ch->next_retry = now + milliseconds(100) * ar.req.alarm_cr.rta_timeout_factor;
  }
}

void PnDevice::end_ar(ArEnd why, nanoseconds) {
  if (!ar_) return;
  ar_.reset();
  state_ = PnDeviceState::Idle;
  std::fill(from_plc_.begin(), from_plc_.end(), 0);
  delayed_head_ = delayed_tail_;
  if (why == ArEnd::Released) {
    emit({PnDeviceEvent::Kind::Released, {}, why});
  } else {
    // The connection is gone without a Release: the model's own reaction
    // (e.g. a safety device's passivation), as DeviceNet's slave does.
    model_->io_connection_lost();
    emit({PnDeviceEvent::Kind::Lost, {}, why});
  }
}

// ---------------------------------------------------------------- alarms

bool PnDevice::raise_alarm(AlarmKind kind, std::uint16_t usi, std::span<const std::uint8_t> data) {
  if (!ar_ || state_ != PnDeviceState::DataExchange) return false;
  Ar& ar = *ar_;
  const bool high = kind == AlarmKind::Process;
  AlarmChannel& ch = high ? ar.alarm_high : ar.alarm_low;
  if (ch.pending) return false;
  const SubmoduleDescription* io = cfg_.description.io_submodule();
  const ModuleDescription* mod = cfg_.description.module_of(io);
  AlarmNotification n;
  n.high_priority = high;
  n.alarm_type = high ? alarm_type::kProcess : alarm_type::kDiagnosis;
  n.api = io->api;
  n.slot = mod->slot;
  n.subslot = io->subslot;
  n.module_ident = mod->module_ident;
  n.submodule_ident = io->submodule_ident;
  ar.alarm_sequence =
      static_cast<std::uint16_t>((ar.alarm_sequence + 1) & alarm_specifier::kSequenceMask);
  n.alarm_specifier = ar.alarm_sequence;
  n.user_structure_identifier = usi;
  if (!data.empty()) {
    n.data.assign(data.begin(), data.end());
  } else if (!high && usi == kUsiChannelDiagnosis) {
    // ChannelDiagnosis: ChannelNumber 0x8000 (the whole submodule),
    // ChannelProperties 0x0800 (specifier "appears"), ChannelErrorType
    // 0x0009 ("error").
    n.data = {0x80, 0x00, 0x08, 0x00, 0x00, 0x09};
    n.alarm_specifier |= alarm_specifier::kChannelDiagnosis |
                         alarm_specifier::kSubmoduleDiagnosisState |
                         alarm_specifier::kArDiagnosisState;
  } else {
    n.user_structure_identifier = usi == kUsiChannelDiagnosis ? std::uint16_t{0x0001} : usi;
    n.data = {0x00, 0x01};
  }
  RtaHeader h;
  h.dst_endpoint = ar.req.alarm_cr.local_alarm_reference;
  h.src_endpoint = kOurAlarmReference;
  h.pdu_type = rta::kTypeData;
  h.send_seq = rta::next_seq(ch.send_seq);
  h.ack_seq = ch.rx_seq;
  ch.high = high;
  ch.send_seq = h.send_seq;
  ch.frame = encode_alarm_notification(ar.controller_mac, mac_, h, n);
  ch.pending = true;
  ch.transport_acked = false;
  ch.retries_left = ar.req.alarm_cr.rta_retries;
  ch.specifier = n.alarm_specifier;
  ch.next_retry = now_ + milliseconds(100) * ar.req.alarm_cr.rta_timeout_factor;
  send_eth(ch.frame);
  ++counters_.alarms_sent;
  return true;
}

void PnDevice::on_alarm(std::uint16_t frame_id, const Mac& src, std::span<const std::uint8_t> pdu,
                        nanoseconds now) {
  if (!ar_ || src != ar_->controller_mac) return;
  RtaPdu p;
  if (!decode_rta(frame_id, pdu, p)) {
    ++counters_.frames_bad;
    return;
  }
  Ar& ar = *ar_;
  if (p.header.dst_endpoint != kOurAlarmReference) return;
  const bool high = frame_id == frame_id::kAlarmHigh;
  AlarmChannel& ch = high ? ar.alarm_high : ar.alarm_low;
  const std::uint8_t type = p.header.pdu_type & 0x0F;
  if (type == rta::kTypeErr) {
    end_ar(ArEnd::Aborted, now);
    return;
  }
  // Any PDU acknowledging our last DATA ends its repeats.
  if (ch.pending && p.header.ack_seq == ch.send_seq) ch.transport_acked = true;
  if (type != rta::kTypeData) return;
  // A DATA-RTA: acknowledge it (again, if it is a repeat of the last one).
  const bool fresh = p.header.send_seq == rta::next_seq(ch.rx_seq);
  if (fresh) ch.rx_seq = p.header.send_seq;
  RtaHeader ack;
  ack.dst_endpoint = ar.req.alarm_cr.local_alarm_reference;
  ack.src_endpoint = kOurAlarmReference;
  ack.pdu_type = rta::kTypeAck;
  ack.add_flags = rta::kAddFlagsWindow1;
  ack.send_seq = ch.send_seq;
  ack.ack_seq = ch.rx_seq;
  send_eth(encode_rta_ack(ar.controller_mac, mac_, high, ack));
  if (fresh && p.ack && ch.pending && p.ack->alarm_specifier == ch.specifier) {
    ch.pending = false;
    ++counters_.alarms_acked;
    emit({PnDeviceEvent::Kind::AlarmAcked});
  }
}

std::string PnDevice::describe() const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s; frames sent %llu, taken %llu, dropped (source %llu, length %llu, "
                "transfer %llu, counter %llu, invalid %llu), by fault %llu; connects %llu "
                "(refused %llu); writes %llu, reads %llu; data-hold expiries %llu; alarms %llu "
                "(repeats %llu, acked %llu)",
                to_string(state_), static_cast<unsigned long long>(counters_.frames_sent),
                static_cast<unsigned long long>(accept_.accepted()),
                static_cast<unsigned long long>(accept_.rejected(OutputReject::WrongSource)),
                static_cast<unsigned long long>(accept_.rejected(OutputReject::WrongLength)),
                static_cast<unsigned long long>(accept_.rejected(OutputReject::TransferStatus)),
                static_cast<unsigned long long>(accept_.rejected(OutputReject::CounterNotAdvanced)),
                static_cast<unsigned long long>(accept_.rejected(OutputReject::DataInvalid)),
                static_cast<unsigned long long>(counters_.frames_dropped_by_fault),
                static_cast<unsigned long long>(counters_.connects),
                static_cast<unsigned long long>(counters_.connects_refused),
                static_cast<unsigned long long>(counters_.writes),
                static_cast<unsigned long long>(counters_.reads),
                static_cast<unsigned long long>(counters_.data_hold_expired),
                static_cast<unsigned long long>(counters_.alarms_sent),
                static_cast<unsigned long long>(counters_.alarm_repeats),
                static_cast<unsigned long long>(counters_.alarms_acked));
  return buf;
}

}  // namespace plc::profinet

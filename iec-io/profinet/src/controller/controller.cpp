#include "plc/profinet/controller/controller.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "controller_device.hpp"
#include "plc/profinet/device/record_status.hpp"
#include "plc/profinet/wire/dcp.hpp"
#include "plc/profinet/wire/ethernet.hpp"
#include "plc/profinet/wire/rpc.hpp"

namespace plc::profinet {

const char* to_string(ArState s) {
  switch (s) {
    case ArState::Waiting:
      return "waiting";
    case ArState::Identifying:
      return "identifying";
    case ArState::Naming:
      return "naming";
    case ArState::Connecting:
      return "connecting";
    case ArState::Writing:
      return "writing";
    case ArState::PrmEnd:
      return "prm-end";
    case ArState::AwaitReady:
      return "await-ready";
    case ArState::Online:
      return "online";
    case ArState::Fault:
      return "fault";
  }
  return "?";
}

const char* to_string(BadFrame b) {
  switch (b) {
    case BadFrame::Decode:
      return "decode";
    case BadFrame::SourceMac:
      return "source-mac";
    case BadFrame::Length:
      return "length";
    case BadFrame::TransferStatus:
      return "transfer-status";
    case BadFrame::DataInvalid:
      return "data-invalid";
    case BadFrame::StaleCounter:
      return "stale-counter";
    case BadFrame::UnknownFrameId:
      return "unknown-frame-id";
    case BadFrame::Rpc:
      return "rpc";
    case BadFrame::kCount:
      break;
  }
  return "?";
}

namespace {
void bad(DeviceCounters& c, BadFrame b) { ++c.bad[static_cast<int>(b)]; }

// A RecordError of 0x100 and above is a device code (RecordRequest::fail).
void fail_record(io::RecordRequest* r, io::RecordError e) {
  const auto v = static_cast<std::uint16_t>(e);
  if (v >= 0x100)
    r->fail(io::RecordError::InvalidIndex, v);
  else
    r->fail(e == io::RecordError::None ? io::RecordError::InvalidState : e);
}

// Whether run_device() would do nothing at all: online, no RPC call and no
// AlarmAck out, the data hold not expired, no record request queued. Each
// clause is one of run_device()'s conditions for acting (in its order);
// most polls in data exchange meet them all and make no call.
bool idle_online(const Controller::Device& d, TIME now, std::uint16_t data_hold_factor) {
  return d.state == ArState::Online && d.call == RpcCall::None && !d.alarm[0].ack_pending &&
         !d.alarm[1].ack_pending &&
         !(d.cyclic && d.rx_seen && now - d.last_input > d.interval * data_hold_factor) &&
         !d.link.maybe_queued();
}

std::string status_text(const PnioStatus& s) {
  char b[64];
  std::snprintf(b, sizeof b, "PNIO status %02X %02X %02X %02X", s.error_code, s.error_decode,
                s.error_code1, s.error_code2);
  return b;
}

}  // namespace

Controller::Controller(const ControllerConfig& cfg, EthernetPort* eth, UdpPort* udp)
    : cfg_(cfg),
      eth_(eth),
      mac_(eth ? eth->mac() : Mac{}),
      udp_(udp),
      eth_queued_(eth ? eth->queued_count() : nullptr),
      udp_queued_(udp ? udp->queued_count() : nullptr),
      rx_(std::max(kMaxFrameLength, kMaxDatagram)) {}
Controller::~Controller() = default;

void Controller::attach(EthernetPort* eth, UdpPort* udp) {
  eth_ = eth;
  mac_ = eth ? eth->mac() : Mac{};
  udp_ = udp;
  eth_queued_ = eth ? eth->queued_count() : nullptr;
  udp_queued_ = udp ? udp->queued_count() : nullptr;
}

std::size_t Controller::add(const ControllerDevice& cfg) {
  if (const std::string why = check(cfg.desc); !why.empty()) throw std::invalid_argument(why);
  auto d = std::make_unique<Device>();
  d->cfg = cfg;
  d->index = devices_.size();
  d->in.assign(cfg.desc.input_size(), 0);
  d->out.assign(cfg.desc.output_size(), 0);
  // A trial plan: refuses what cannot be connected before anything starts.
  (void)plan_connect(cfg_, cfg.desc, Mac{}, Uuid{}, 1, 0xC000);
  if (!cfg.record_target_given) {
    const SubmoduleDescription* s = cfg.desc.io_submodule();
    const ModuleDescription* m = cfg.desc.module_of(s);
    if (s && m) {
      d->cfg.record_api = s->api;
      d->cfg.record_slot = m->slot;
      d->cfg.record_subslot = s->subslot;
    }
  }
  in_views_.emplace_back(d->in);
  out_views_.emplace_back(d->out);
  devices_.push_back(std::move(d));
  return devices_.size() - 1;
}

io::DeviceLink& Controller::link(std::size_t d) { return devices_[d]->link; }
ArState Controller::state(std::size_t d) const { return devices_[d]->state; }
const DeviceCounters& Controller::counters(std::size_t d) const { return devices_[d]->counters; }
std::size_t Controller::size() const { return devices_.size(); }

bool Controller::releasing() const {
  for (const auto& d : devices_)
    if (d->releasing) return true;
  return false;
}

// ---- the poll loop -----------------------------------------------------------

void Controller::poll(TIME now) {
  if (!eth_ || !udp_) return;
  // Each frame read where the port holds it (the memory hub's buffer: no
  // copy), valid until the next receive.
  const auto may_hold = [](const std::atomic<std::size_t>* q) {
    return !q || q->load(std::memory_order_relaxed) != 0;
  };
  for (int n = 0; n < 4096 && may_hold(eth_queued_); ++n) {
    const std::span<const std::uint8_t> frame = eth_->receive_view(rx_, TIME(0));
    if (frame.empty()) break;
    on_ethernet(frame, now);
  }
  for (int n = 0; n < 256 && may_hold(udp_queued_); ++n) {
    Ipv4 ip;
    std::uint16_t port = 0;
    const std::size_t len = udp_->receive_from(rx_, ip, port, TIME(0));
    if (len == 0) break;
    on_udp(std::span<const std::uint8_t>(rx_).first(len), ip, port, now);
  }
  TIME due = now + cfg_.send_interval();
  for (auto& d : devices_) {
    if (!idle_online(*d, now, cfg_.data_hold_factor)) run_device(*d, now);
    if (d->cyclic) {
      // Due within half an interval: send now (a wake-up a little early
      // must not slip the frame by a whole interval).
      if (now + d->interval / 2 >= d->next_send) send_cyclic(*d, now);
      due = std::min(due, d->next_send);
    }
  }
  next_due_ = due;
}

// ---- Ethernet: DCP, cyclic, alarms --------------------------------------------

// Inline in poll(), its one caller: the cyclic frames (all but a few) take
// no call; alarms and DCP go on in on_acyclic().
[[gnu::always_inline]] inline void Controller::on_ethernet(std::span<const std::uint8_t> frame,
                                                           TIME now) {
  PnFrameView v;
  if (!decode_pn_frame(frame, v)) {
    ++unmatched_;
    return;
  }
  if (v.dst != mac_) return;  // not ours (a hub / promiscuous port shows all traffic)
  if (is_rt_class1(v.frame_id)) {
    for (auto& dp : devices_) {
      Device& d = *dp;
      if (!d.cyclic || d.input_frame_id != v.frame_id) continue;
      if (v.src != d.mac) return bad(d.counters, BadFrame::SourceMac);
      CyclicView c;
      if (const WireStatus st = decode_cyclic(v, d.plan.layout.input.c_sdu_length, c); !st)
        return bad(d.counters, st.error == WireError::Truncated || st.error == WireError::BadLength
                                   ? BadFrame::Length
                                   : BadFrame::Decode);
      if (c.header.transfer_status != 0) return bad(d.counters, BadFrame::TransferStatus);
      if (!(c.header.data_status & data_status::kDataValid))
        return bad(d.counters, BadFrame::DataInvalid);
      if (d.rx_seen) {
        if (!cycle_counter_advanced(d.last_rx_counter, c.header.cycle_counter))
          return bad(d.counters, BadFrame::StaleCounter);
        const std::uint16_t delta =
            static_cast<std::uint16_t>(c.header.cycle_counter - d.last_rx_counter);
        if (d.counter_step > 0 && delta > d.counter_step)
          d.counters.lost += delta / d.counter_step - 1;
      }
      d.rx_seen = true;
      d.last_rx_counter = c.header.cycle_counter;
      d.last_input = now;
      ++d.counters.frames_in;
      if (d.state != ArState::Online) return;
      // Inputs of a submodule whose IOPS is bad read as zero.
      for (const auto& u : d.plan.inputs) {
        auto dst = std::span<std::uint8_t>(d.in).subspan(u.user_offset, u.object.length);
        if (iops(c.c_sdu, u.object) & iocr::kIoxsGood) {
          const auto src = io_data(c.c_sdu, u.object);
          copy_io_bytes(dst.data(), src.data(), src.size());
        } else {
          std::fill(dst.begin(), dst.end(), 0);
        }
      }
      return;
    }
    ++unmatched_;  // no AR of ours uses this FrameID
    return;
  }
  on_acyclic(v, now);
}

void Controller::on_acyclic(const PnFrameView& v, TIME now) {
  if (is_alarm(v.frame_id)) {
    for (auto& dp : devices_)
      if (dp->cyclic && dp->mac == v.src) return on_alarm(*dp, v.frame_id, v.pdu, now);
    ++unmatched_;
    return;
  }
  if (v.frame_id == frame_id::kDcpIdentifyResponse || v.frame_id == frame_id::kDcpGetSet) {
    DcpMessage m;
    if (!decode_dcp(v.frame_id, v.pdu, m)) {
      ++unmatched_;
      return;
    }
    for (auto& dp : devices_) {
      Device& d = *dp;
      if (m.xid != d.xid) continue;
      if (d.state == ArState::Identifying && m.service_id == dcp::kServiceIdentify) {
        DcpIdentity id;
        if (!identity_from(m, id) || id.station_name != d.cfg.desc.station_name)
          return bad(d.counters, BadFrame::Decode);
        d.mac = v.src;
        const bool ip_ok = id.ip.ip == d.cfg.desc.ip.host_order;
        if (!ip_ok && d.cfg.set_ip) return dcp_set(d, now, /*name=*/false);
        if (!ip_ok)
          return fault(d, now,
                       "the device named '" + d.cfg.desc.station_name + "' has IP " +
                           to_string(Ipv4{id.ip.ip}) + ", the config says " +
                           to_string(d.cfg.desc.ip) + " (set_ip: true lets the controller set it)");
        return connect(d, now);
      }
      if (d.state == ArState::Naming && m.service_id == dcp::kServiceSet) {
        std::vector<DcpSetResult> results;
        if (!set_results_from(m, results)) return bad(d.counters, BadFrame::Decode);
        for (const auto& r : results)
          if (r.error != dcp::kErrorOk)
            return fault(d, now,
                         "DCP Set refused (option " + std::to_string(r.option) + "/" +
                             std::to_string(r.suboption) + ", error " + std::to_string(r.error) +
                             ")");
        if (!d.name_set) {
          d.name_set = true;
          return identify(d, now);
        }
        return connect(d, now);  // the IP is set
      }
    }
  }
}

void Controller::on_alarm(Device& d, std::uint16_t frame_id, std::span<const std::uint8_t> pdu,
                          TIME now) {
  RtaPdu p;
  if (!decode_rta(frame_id, pdu, p)) return bad(d.counters, BadFrame::Decode);
  if (p.header.dst_endpoint != d.alarm_local_ref) return bad(d.counters, BadFrame::Decode);
  const bool high = frame_id == frame_id::kAlarmHigh;
  Device::AlarmChannel& ch = d.alarm[high ? 1 : 0];
  const std::uint8_t type = p.header.pdu_type & 0x0F;
  if (type == rta::kTypeErr) {
    return lose(
        d, now,
        "the device aborted the AR (ERR-RTA, " + status_text(p.error.value_or(PnioStatus{})) + ")");
  }
  if (type == rta::kTypeAck || type == rta::kTypeData) {
    // Either acknowledges our AlarmAck.
    if (ch.ack_pending && p.header.ack_seq == ch.send_seq) ch.ack_pending = false;
  }
  if (type != rta::kTypeData) return;
  RtaHeader ack;
  ack.dst_endpoint = d.alarm_remote_ref;
  ack.src_endpoint = d.alarm_local_ref;
  ack.pdu_type = rta::kTypeAck;
  ack.add_flags = rta::kAddFlagsWindow1;
  ack.send_seq = ch.send_seq;
  ack.ack_seq = p.header.send_seq;
  const bool repeat = p.header.send_seq == ch.rx_seq;  // our ACK got lost: ACK again only
  if (!repeat && p.header.send_seq != rta::next_seq(ch.rx_seq))
    return bad(d.counters, BadFrame::Decode);
  const auto ack_frame = encode_rta_ack(d.mac, mac_, high, ack);
  eth_->send(ack_frame);
  if (repeat || !p.notification) return;
  ch.rx_seq = p.header.send_seq;
  const AlarmNotification& n = *p.notification;
  ++d.counters.alarms;
  io::DeviceAlarm a;
  a.type = n.alarm_type;
  a.slot = n.slot;
  a.subslot = n.subslot;
  a.usi = n.user_structure_identifier.value_or(0);
  for (std::size_t i = 0; i < 4 && i < n.data.size(); ++i) a.data = (a.data << 8) | n.data[i];
  a.appears = n.alarm_type != alarm_type::kDiagnosisDisappears;
  d.link.post_alarm(a);
  char b[160];
  std::snprintf(b, sizeof b, "type %u slot %u subslot 0x%04X usi 0x%04X data 0x%08X",
                static_cast<unsigned>(n.alarm_type), static_cast<unsigned>(n.slot),
                static_cast<unsigned>(n.subslot), static_cast<unsigned>(a.usi),
                static_cast<unsigned>(a.data));
  d.last_alarm = b;
  if (on_change) on_change(d.index, d.state, std::string("alarm ") + b);
  // The application's acknowledgement (AlarmAck in a DATA-RTA), repeated
  // until the device's ACK-RTA comes.
  RtaHeader h;
  h.dst_endpoint = d.alarm_remote_ref;
  h.src_endpoint = d.alarm_local_ref;
  h.pdu_type = rta::kTypeData;
  h.add_flags = rta::kAddFlagsWindow1 | rta::kAddFlagTack;
  ch.send_seq = rta::next_seq(ch.send_seq);
  h.send_seq = ch.send_seq;
  h.ack_seq = ch.rx_seq;
  ch.ack_frame = encode_alarm_ack(d.mac, mac_, h, ack_for(n));
  ch.ack_pending = true;
  ch.ack_tries = 1;
  ch.ack_deadline =
      now + std::chrono::milliseconds(100) * d.plan.request.alarm_cr.rta_timeout_factor;
  eth_->send(ch.ack_frame);
}

// ---- UDP: RPC responses and the device's ApplicationReady ---------------------

void Controller::on_udp(std::span<const std::uint8_t> data, Ipv4 ip, std::uint16_t port, TIME now) {
  RpcPdu pdu;
  Device* from = nullptr;
  for (auto& dp : devices_)
    if (dp->cfg.desc.ip == ip) from = dp.get();
  if (!decode_rpc(data, pdu)) {
    if (from)
      bad(from->counters, BadFrame::Rpc);
    else
      ++unmatched_;
    return;
  }
  if (!from) {
    ++unmatched_;
    return;
  }
  Device& d = *from;
  const RpcHeader& h = pdu.header;
  if (h.packet_type == rpc::kRequest) return on_rpc_request(d, pdu, ip, port, now);
  if (h.activity != d.activity || d.call == RpcCall::None || h.sequence_number != d.call_seq)
    return bad(d.counters, BadFrame::Rpc);     // late (after its timeout) or not ours
  if (h.packet_type == rpc::kWorking) return;  // the device is busy with it: keep waiting
  const RpcCall call = d.call;
  d.call = RpcCall::None;
  NdrResponse res;
  if (h.packet_type != rpc::kResponse || !decode_ndr_response(pdu.body, h.little_endian, res)) {
    bad(d.counters, BadFrame::Rpc);
    const std::string why =
        h.packet_type == rpc::kResponse
            ? "malformed RPC response"
            : "RPC " + std::string(h.packet_type == rpc::kReject ? "reject" : "fault");
    if (call == RpcCall::Read || call == RpcCall::RecordWrite) {
      ++d.counters.records_error;
      if (d.record) d.record->fail(io::RecordError::InvalidState);
      d.record = nullptr;
      return;
    }
    if (call == RpcCall::Release) {
      d.releasing = false;
      return;
    }
    return fault(d, now, why);
  }
  on_rpc_response(d, call, res, now);
}

void Controller::on_rpc_response(Device& d, RpcCall call, const NdrResponse& res, TIME now) {
  switch (call) {
    case RpcCall::None:
      return;
    case RpcCall::Connect: {
      if (!res.status.ok()) {
        ++d.counters.connect_errors;
        return fault(d, now, "Connect refused: " + status_text(res.status));
      }
      ConnectResponse cr;
      if (const WireStatus st = decode_connect_response(res.args, cr); !st) {
        bad(d.counters, BadFrame::Rpc);
        ++d.counters.connect_errors;
        return fault(d, now, std::string("malformed Connect response: ") + st.reason);
      }
      if (cr.ar.ar_uuid != d.ar_uuid) {
        ++d.counters.connect_errors;
        return fault(d, now, "Connect response for another AR");
      }
      if (cr.module_diff) {
        for (const auto& api : cr.module_diff->apis)
          for (const auto& m : api.modules)
            for (const auto& s : m.submodules)
              if (s.state != submodule_state::kOk || m.state != module_state::kProperModule) {
                char b[160];
                std::snprintf(
                    b, sizeof b,
                    "the device's module differs from the description: API 0x%X slot "
                    "%u subslot 0x%04X (module ident 0x%X, submodule ident 0x%X, state "
                    "0x%04X)",
                    static_cast<unsigned>(api.api), static_cast<unsigned>(m.slot),
                    static_cast<unsigned>(s.subslot), static_cast<unsigned>(m.module_ident),
                    static_cast<unsigned>(s.submodule_ident), static_cast<unsigned>(s.state));
                ++d.counters.connect_errors;
                release(d, now);
                return fault(d, now, b);
              }
      }
      for (const auto& io : cr.iocrs) {
        if (io.iocr_type == iocr::kTypeOutput) d.output_frame_id = io.frame_id;
        if (io.iocr_type == iocr::kTypeInput) d.input_frame_id = io.frame_id;
      }
      d.alarm_remote_ref = cr.alarm_cr.local_alarm_reference;
      // Output frames start now, IOPS/IOCS good from the first one
      // (fieldbus-masters.md §1 item 6).
      start_cyclic(d, now);
      return write_startup(d, now);
    }
    case RpcCall::Write: {
      WriteResponse wr;
      if (!res.status.ok() || !decode_write_response(res.args, wr) || !wr.header.status.ok()) {
        ++d.counters.connect_errors;
        std::string why = "start-up record write refused: " + status_text(res.status);
        for (const auto& s : wr.sub_results)
          if (!s.status.ok())
            why += "; index 0x" +
                   [&] {
                     char b[16];
                     std::snprintf(b, sizeof b, "%04X", s.index);
                     return std::string(b);
                   }() +
                   " " + status_text(s.status);
        release(d, now);
        return fault(d, now, why);
      }
      return prm_end(d, now);
    }
    case RpcCall::PrmEnd: {
      ControlBlock c;
      if (!res.status.ok() || !decode_control(res.args, c) || c.block_type != block::kPrmEndRes) {
        ++d.counters.connect_errors;
        release(d, now);
        return fault(d, now, "PrmEnd refused: " + status_text(res.status));
      }
      if (d.state == ArState::PrmEnd) {
        d.state = ArState::AwaitReady;
        d.deadline = now + cfg_.ready_timeout;
      }
      return;
    }
    case RpcCall::Read:
    case RpcCall::RecordWrite: {
      io::RecordRequest* r = d.record;
      d.record = nullptr;
      if (!r) return;
      if (!res.status.ok()) {
        ++d.counters.records_error;
        // The device's refusal, as the FBs know it from the sim plugin
        // (record_status.hpp: the PNIORW codes both ends use).
        return fail_record(r, record_error_from(res.status));
      }
      if (call == RpcCall::RecordWrite) {
        WriteResponse wr;
        if (!decode_write_response(res.args, wr)) {
          ++d.counters.records_error;
          bad(d.counters, BadFrame::Rpc);
          return r->fail(io::RecordError::InvalidState);
        }
        if (!wr.header.status.ok()) {
          ++d.counters.records_error;
          return fail_record(r, record_error_from(wr.header.status));
        }
        ++d.counters.records_ok;
        return r->complete(r->data().size());
      }
      RecordResponseHeader h;
      std::span<const std::uint8_t> data;
      if (!decode_read_response(res.args, h, data)) {
        ++d.counters.records_error;
        bad(d.counters, BadFrame::Rpc);
        return r->fail(io::RecordError::InvalidState);
      }
      if (data.size() > r->buffer().size()) {
        ++d.counters.records_error;
        return r->fail(io::RecordError::InvalidLength);
      }
      std::copy(data.begin(), data.end(), r->buffer().begin());
      ++d.counters.records_ok;
      return r->complete(data.size());
    }
    case RpcCall::Release:
      d.releasing = false;
      return;
  }
}

void Controller::on_rpc_request(Device& d, const RpcPdu& pdu, Ipv4 ip, std::uint16_t port,
                                TIME now) {
  const RpcHeader& h = pdu.header;
  NdrRequest req;
  ControlBlock c;
  if (h.opnum != rpc::kOpControl || !decode_ndr_request(pdu.body, h.little_endian, req) ||
      !decode_control(req.args, c) || c.block_type != block::kApplicationReadyReq) {
    return bad(d.counters, BadFrame::Rpc);
  }
  if (c.ar_uuid != d.ar_uuid || !d.cyclic) return bad(d.counters, BadFrame::Rpc);
  // Answer with PNIOStatus 0, block 0x8112 and ControlCommand DONE (an echo
  // of the request would make the device raise an alarm; §1 item 5).
  const ControlBlock done = control_response_for(c);
  const auto args = encode_control(done);
  const auto body = encode_ndr_response(PnioStatus{}, req.args_maximum, args, h.little_endian);
  const auto dgram = encode_rpc(response_header_for(h), body);
  udp_->send_to(ip, port, dgram);
  if (d.state == ArState::PrmEnd || d.state == ArState::AwaitReady) d.app_ready = true;
  (void)now;
}

// ---- the state machine ---------------------------------------------------------

void Controller::run_device(Device& d, TIME now) {
  // An RPC call without an answer in time.
  if (d.call != RpcCall::None && now >= d.call_deadline) {
    const RpcCall call = d.call;
    d.call = RpcCall::None;
    if (call == RpcCall::Read || call == RpcCall::RecordWrite) {
      ++d.counters.records_timeout;
      if (d.record) d.record->fail(io::RecordError::Timeout);
      d.record = nullptr;
    } else if (call == RpcCall::Release) {
      d.releasing = false;
    } else {
      ++d.counters.connect_errors;
      const char* what = call == RpcCall::Connect ? "Connect"
                         : call == RpcCall::Write ? "the start-up record write"
                                                  : "PrmEnd";
      return lose(d, now, std::string("no answer to ") + what);
    }
  }
  // Alarm acknowledgements without the device's ACK-RTA: repeat, then give up.
  if (d.alarm[0].ack_pending || d.alarm[1].ack_pending) {  // mostly: none out
    for (auto& ch : d.alarm) {
      if (!ch.ack_pending || now < ch.ack_deadline) continue;
      if (ch.ack_tries > d.plan.request.alarm_cr.rta_retries)
        return lose(d, now, "the device does not acknowledge our AlarmAck");
      ++ch.ack_tries;
      ch.ack_deadline =
          now + std::chrono::milliseconds(100) * d.plan.request.alarm_cr.rta_timeout_factor;
      eth_->send(ch.ack_frame);
    }
  }
  switch (d.state) {
    case ArState::Waiting:
    case ArState::Fault:
      if (now >= d.next_try && !d.releasing) {
        if (d.cfg.set_name && !d.name_set) return dcp_set(d, now, /*name=*/true);
        return identify(d, now);
      }
      return;
    case ArState::Identifying:
    case ArState::Naming:
      if (now >= d.deadline)
        return lose(d, now,
                    d.state == ArState::Identifying
                        ? "no device named '" + d.cfg.desc.station_name + "' answers DCP Identify"
                        : std::string("no answer to DCP Set"));
      return;
    case ArState::AwaitReady:
      if (d.app_ready && d.rx_seen) {
        d.state = ArState::Online;
        ++d.counters.connects;
        d.last_error.clear();
        d.link.set_state(io::DeviceState::Online);
        changed(d);
        break;
      }
      if (now >= d.deadline) {
        ++d.counters.connect_errors;
        return lose(d, now,
                    d.app_ready ? "no valid input frame after ApplicationReady"
                                : "no ApplicationReady from the device");
      }
      break;
    default:
      break;
  }
  // The data-hold watchdog: from the first valid input frame on.
  if (d.cyclic && d.rx_seen && now - d.last_input > d.interval * cfg_.data_hold_factor) {
    const auto ms = std::chrono::duration_cast<std::chrono::microseconds>(now - d.last_input);
    char b[128];
    std::snprintf(b, sizeof b, "no valid input frame for %.1f ms (data hold %u x %.3f ms)",
                  static_cast<double>(ms.count()) / 1000.0,
                  static_cast<unsigned>(cfg_.data_hold_factor),
                  static_cast<double>(d.interval.count()) / 1e6);
    return lose(d, now, b);
  }
  if (d.state != ArState::Online || d.call != RpcCall::None) return;
  // maybe_queued(): most steps have no request, and pop() takes a lock.
  if (io::RecordRequest* r = d.link.maybe_queued() ? d.link.pop() : nullptr) {
    d.record = r;
    if (r->kind() == io::RecordKind::Read) {
      RecordRequestHeader h;
      h.seq_number = d.record_seq++;
      h.ar_uuid = d.ar_uuid;
      h.api = d.cfg.record_api;
      h.slot = d.cfg.record_slot;
      h.subslot = d.cfg.record_subslot;
      h.index = r->index();
      h.record_data_length = io::kRecordMaxBytes;
      encode_read_request_to(call_args_, h);
      call(d, RpcCall::Read, rpc::kOpRead, call_args_, now, cfg_.record_timeout);
    } else {
      // One record, not as MultipleWrite (encode_write_request() with one
      // RecordWrite builds the same bytes).
      RecordRequestHeader h;
      h.seq_number = d.record_seq++;
      h.ar_uuid = d.ar_uuid;
      h.api = d.cfg.record_api;
      h.slot = d.cfg.record_slot;
      h.subslot = d.cfg.record_subslot;
      h.index = r->index();
      encode_write_request_to(call_args_, h, r->data());
      call(d, RpcCall::RecordWrite, rpc::kOpWrite, call_args_, now, cfg_.record_timeout);
    }
  }
}

void Controller::identify(Device& d, TIME now) {
  d.state = ArState::Identifying;
  d.xid = 0x50C00000u | (static_cast<std::uint32_t>(d.index) << 12) | ((d.xid + 1) & 0xFFF);
  d.deadline = now + cfg_.dcp_timeout;
  eth_->send(encode_dcp_identify_request(mac_, d.xid, d.cfg.desc.station_name, 1));
}

void Controller::dcp_set(Device& d, TIME now, bool name) {
  d.state = ArState::Naming;
  d.xid = 0x50C00000u | (static_cast<std::uint32_t>(d.index) << 12) | ((d.xid + 1) & 0xFFF);
  d.deadline = now + cfg_.dcp_timeout;
  DcpSetRequest r;
  if (name) {
    r.station_name = d.cfg.desc.station_name;
  } else {
    r.ip = DcpIpSuite{d.cfg.desc.ip.host_order, d.cfg.desc.netmask.host_order,
                      d.cfg.desc.gateway.host_order};
  }
  r.permanent = true;
  const Mac to = name ? d.cfg.mac : d.mac;
  if (name) d.mac = d.cfg.mac;
  eth_->send(encode_dcp_set_request(to, mac_, d.xid, r));
}

void Controller::connect(Device& d, TIME now) {
  const std::uint32_t n = next_ar_++;
  const Mac me = mac_;
  std::uint64_t hi = 0;
  for (auto b : me) hi = (hi << 8) | b;
  d.ar_uuid = make_uuid_v4(hi << 16 | d.index, n);
  d.activity = make_uuid_v4(hi << 16 | 0x8000 | d.index, n);
  d.session_key = static_cast<std::uint16_t>(n);
  d.input_frame_id = static_cast<std::uint16_t>(0xC000 + 2 * d.index);
  d.plan = plan_connect(cfg_, d.cfg.desc, me, d.ar_uuid, d.session_key, d.input_frame_id);
  d.alarm_local_ref = d.plan.request.alarm_cr.local_alarm_reference;
  d.interval = std::chrono::nanoseconds(31250) * cfg_.send_clock_factor *
               d.plan.request.iocrs[0].reduction_ratio;
  d.counter_step =
      static_cast<std::uint16_t>(cfg_.send_clock_factor * d.plan.request.iocrs[0].reduction_ratio);
  d.alarm = {};
  d.app_ready = false;
  d.rx_seen = false;
  d.state = ArState::Connecting;
  call(d, RpcCall::Connect, rpc::kOpConnect, encode_connect_request(d.plan.request), now,
       cfg_.rpc_timeout);
}

void Controller::write_startup(Device& d, TIME now) {
  std::vector<RecordWrite> records;
  for (const ModuleDescription& m : d.cfg.desc.modules)
    for (const SubmoduleDescription& s : m.submodules)
      for (const StartupRecord& r : s.records)
        records.push_back({s.api, m.slot, s.subslot, r.index, r.data});
  if (records.empty()) return prm_end(d, now);
  d.state = ArState::Writing;
  call(d, RpcCall::Write, rpc::kOpWrite,
       encode_write_request(d.record_seq++, d.ar_uuid, records, /*force_multiple=*/true), now,
       cfg_.rpc_timeout);
}

void Controller::prm_end(Device& d, TIME now) {
  d.state = ArState::PrmEnd;
  ControlBlock c;
  c.block_type = block::kPrmEndReq;
  c.ar_uuid = d.ar_uuid;
  c.session_key = d.session_key;
  c.command = control::kPrmEnd;
  call(d, RpcCall::PrmEnd, rpc::kOpControl, encode_control(c), now, cfg_.rpc_timeout);
}

void Controller::release(Device& d, TIME now) {
  if (!d.cyclic) return;
  stop_cyclic(d);
  ControlBlock c;
  c.block_type = block::kReleaseReq;
  c.ar_uuid = d.ar_uuid;
  c.session_key = d.session_key;
  c.command = control::kRelease;
  if (d.record) d.record->fail(io::RecordError::NotReachable);
  d.record = nullptr;
  d.releasing = true;
  call(d, RpcCall::Release, rpc::kOpRelease, encode_control(c), now, cfg_.rpc_timeout);
}

void Controller::release_all(TIME now) {
  for (auto& d : devices_) {
    const bool was_online = d->state == ArState::Online;
    release(*d, now);
    drop_link(*d);
    d->state = ArState::Waiting;
    d->next_try = TIME::max();  // stopped: no reconnect
    if (was_online) changed(*d);
  }
}

void Controller::call(Device& d, RpcCall call, std::uint16_t opnum,
                      std::span<const std::uint8_t> args, TIME now, TIME timeout) {
  RpcHeader h;
  h.packet_type = rpc::kRequest;
  h.flags1 = rpc::kFlagIdempotent;
  h.little_endian = true;
  h.object = pnio_object_uuid(d.cfg.desc.instance, d.cfg.desc.device_id, d.cfg.desc.vendor_id);
  h.interface = kPnioDeviceInterface;
  h.activity = d.activity;
  h.sequence_number = d.rpc_seq++;
  h.opnum = opnum;
  encode_ndr_request_to(call_body_, rpc::kMaxArgs, args, true);
  encode_rpc_to(call_dgram_, h, call_body_);
  d.call = call;
  d.call_seq = h.sequence_number;
  d.call_deadline = now + timeout;
  udp_->send_to(d.cfg.desc.ip, kRpcUdpPort, call_dgram_);
}

// ---- cyclic data ------------------------------------------------------------

void Controller::start_cyclic(Device& d, TIME now) {
  d.cyclic = true;
  d.connected_at = now;
  d.next_send = now;
  d.cycle_counter = 0;
  const std::size_t length = d.plan.layout.output.c_sdu_length;
  d.tx.assign(cyclic_frame_length(length, true), 0);
  // The C_SDU lives in the frame: each send writes the outputs into it and
  // the header around it. IOCS of every input-CR submodule: good, from the
  // first frame on (a layout is at most 1440 bytes: the span is there).
  const std::span<std::uint8_t> c_sdu = cyclic_c_sdu(d.tx, length, true);
  d.tx_c_sdu = c_sdu;
  d.tx_c_sdu_length = length;
  if (!c_sdu.empty()) {
    for (const IocsSlot& s : d.plan.layout.output.iocs) c_sdu[s.offset] = iocr::kIoxsGood;
    for (const IoDataObject& o : d.plan.layout.output.data)
      c_sdu[o.iops_offset()] = iocr::kIoxsGood;
  }
  // The Ethernet header and FrameID are the AR's (the device's MAC, ours,
  // the output FrameID): written once, each send writes only the outputs
  // and the APDU status.
  CyclicHeader h;
  h.dst = d.mac;
  h.src = mac_;
  h.vlan_tci = kVlanTciPriority6;
  h.frame_id = d.output_frame_id;
  d.tx_length = finish_cyclic(d.tx, h, length);
  send_cyclic(d, now);
}

void Controller::stop_cyclic(Device& d) { d.cyclic = false; }

// Inline in poll() (and start_cyclic()): one call less per output frame.
[[gnu::always_inline]] inline void Controller::send_cyclic(Device& d, TIME now) {
  // Missed intervals (a late wake-up) are skipped and counted, not sent
  // in a burst.
  if (now >= d.next_send + d.interval) {
    const auto missed = (now - d.next_send) / d.interval;
    d.counters.late += static_cast<std::uint64_t>(missed);
    d.next_send += d.interval * missed;
    d.cycle_counter = static_cast<std::uint16_t>(d.cycle_counter + missed * d.counter_step);
  }
  const std::size_t length = d.plan.layout.output.c_sdu_length;
  // The C_SDU's place in tx, from start_cyclic() (tx and the layout are the
  // AR's); computed again should the layout differ.
  if (d.tx_c_sdu_length != length) {
    d.tx_c_sdu = cyclic_c_sdu(d.tx, length, true);
    d.tx_c_sdu_length = length;
  }
  const std::span<std::uint8_t> c_sdu = d.tx_c_sdu;
  for (const auto& u : d.plan.outputs)
    put_io_data(c_sdu, u.object,
                std::span<const std::uint8_t>(d.out).subspan(u.user_offset, u.object.length),
                iocr::kIoxsGood);
  const std::size_t n = d.tx_length > 0 ? put_cyclic_status(d.tx, length, true, d.cycle_counter,
                                                            data_status::kGood, 0)
                                        : 0;
  if (n > 0 && eth_->send(std::span<const std::uint8_t>(d.tx).first(n))) ++d.counters.frames_out;
  d.cycle_counter = static_cast<std::uint16_t>(d.cycle_counter + d.counter_step);
  d.next_send += d.interval;
}

// ---- loss, faults ---------------------------------------------------------------

void Controller::drop_link(Device& d) {
  if (d.record) d.record->fail(io::RecordError::NotReachable);  // the one in flight
  d.record = nullptr;
  if (d.call == RpcCall::Read || d.call == RpcCall::RecordWrite) d.call = RpcCall::None;
  for (io::RecordRequest* r = d.link.pop(); r; r = d.link.pop())
    r->fail(io::RecordError::NotReachable);
  std::fill(d.in.begin(), d.in.end(), 0);  // invalid inputs never look like data
  d.link.set_state(io::DeviceState::Offline);
}

void Controller::lose(Device& d, TIME now, const std::string& why) {
  const bool was_online = d.state == ArState::Online;
  if (was_online) ++d.counters.losses;
  stop_cyclic(d);
  if (d.call != RpcCall::Release) d.call = RpcCall::None;
  drop_link(d);
  d.state = ArState::Waiting;
  d.last_error = why;
  d.next_try = now + cfg_.retry;
  if (was_online) changed(d);
}

void Controller::fault(Device& d, TIME now, const std::string& why) {
  stop_cyclic(d);
  if (d.call != RpcCall::Release) d.call = RpcCall::None;
  const bool was_online = d.state == ArState::Online;
  if (was_online) ++d.counters.losses;
  drop_link(d);
  d.link.set_state(io::DeviceState::Fault);
  d.state = ArState::Fault;
  d.last_error = why;
  d.next_try = now + cfg_.retry;
  changed(d);
}

void Controller::changed(const Device& d) {
  if (on_change) on_change(d.index, d.state, d.last_error);
}

std::string Controller::diagnostics(std::size_t i) const {
  const Device& d = *devices_[i];
  const DeviceCounters& c = d.counters;
  std::string bad_text;
  for (int b = 0; b < static_cast<int>(BadFrame::kCount); ++b)
    if (c.bad[b])
      bad_text +=
          std::string(" ") + to_string(static_cast<BadFrame>(b)) + " " + std::to_string(c.bad[b]);
  char buf[640];
  std::snprintf(
      buf, sizeof buf,
      "profinet %s %s %s; frames out %llu in %llu late %llu lost %llu bad %llu%s%s; connects "
      "%llu (refused %llu) losses %llu alarms %llu records ok %llu err %llu timeout %llu",
      d.cfg.desc.station_name.c_str(), to_string(d.cfg.desc.ip).c_str(), to_string(d.state),
      static_cast<unsigned long long>(c.frames_out), static_cast<unsigned long long>(c.frames_in),
      static_cast<unsigned long long>(c.late), static_cast<unsigned long long>(c.lost),
      static_cast<unsigned long long>(c.bad_total()), bad_text.empty() ? "" : " (",
      bad_text.empty() ? "" : (bad_text.substr(1) + ")").c_str(),
      static_cast<unsigned long long>(c.connects),
      static_cast<unsigned long long>(c.connect_errors), static_cast<unsigned long long>(c.losses),
      static_cast<unsigned long long>(c.alarms), static_cast<unsigned long long>(c.records_ok),
      static_cast<unsigned long long>(c.records_error),
      static_cast<unsigned long long>(c.records_timeout));
  std::string s = buf;
  if (!d.last_alarm.empty()) s += "; last alarm: " + d.last_alarm;
  if (!d.last_error.empty()) s += "; last: " + d.last_error;
  return s;
}

}  // namespace plc::profinet

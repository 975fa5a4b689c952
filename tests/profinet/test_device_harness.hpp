// A PnDevice on the in-memory links with a hand-driven controller: the
// controller side is built only from the wire codec (blocks, RPC, cyclic,
// RTA), so the device is checked against the encoded PDUs, not against our
// own controller. Virtual time: run() advances the clock and polls.
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "plc/io/device_model.hpp"
#include "plc/profinet/description/device_description.hpp"
#include "plc/profinet/device/pn_device.hpp"
#include "plc/profinet/link/memory_ethernet.hpp"
#include "plc/profinet/link/memory_udp.hpp"
#include "plc/profinet/wire/alarm.hpp"
#include "plc/profinet/wire/blocks.hpp"
#include "plc/profinet/wire/cyclic.hpp"
#include "plc/profinet/wire/dcp.hpp"
#include "plc/profinet/wire/rpc.hpp"

namespace pn_test {

namespace pn = plc::profinet;
namespace io = plc::io;
using std::chrono::microseconds;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;

// A model that shows what reached it: inputs = outputs XOR 0xFF; records
// kept by index; index 0x99 refuses with the model code 0x1234.
class EchoModel : public io::DeviceModel {
 public:
  static constexpr std::size_t kBytes = 4;
  [[nodiscard]] std::size_t input_size() const override { return kBytes; }
  [[nodiscard]] std::size_t output_size() const override { return kBytes; }
  void step(plc::TIME, plc::TIME, std::span<const std::uint8_t> from_plc,
            std::span<std::uint8_t> to_plc) override {
    last_outputs.assign(from_plc.begin(), from_plc.end());
    for (std::size_t i = 0; i < to_plc.size(); ++i) to_plc[i] = from_plc[i] ^ 0xFF;
    ++steps;
  }
  io::RecordError read_record(std::uint16_t index, std::span<std::uint8_t> out,
                              std::size_t& length) override {
    const auto it = records.find(index);
    if (it == records.end()) return io::RecordError::InvalidIndex;
    length = std::min(out.size(), it->second.size());
    std::copy_n(it->second.begin(), length, out.begin());
    return io::RecordError::None;
  }
  io::RecordError write_record(std::uint16_t index, std::span<const std::uint8_t> d) override {
    if (index == 0x99) return static_cast<io::RecordError>(0x1234);
    records[index].assign(d.begin(), d.end());
    writes.push_back(index);
    return io::RecordError::None;
  }
  void io_connection_lost() override { ++lost; }

  std::vector<std::uint8_t> last_outputs;
  std::map<std::uint16_t, std::vector<std::uint8_t>> records;
  std::vector<std::uint16_t> writes;
  int steps = 0;
  int lost = 0;
};

// DAP + one IO submodule (slot 1 subslot 1, 4 bytes each way).
inline pn::DeviceDescription echo_description() {
  pn::DeviceDescription d;
  d.station_name = "echo-1";
  d.ip = pn::Ipv4{0x0A000002};
  d.vendor_id = 0x0FFF;
  d.device_id = 0x0042;
  d.modules.push_back({0,
                       0x00000001,
                       {{pn::kDapSubslot, 0, 0x1, 0, 0, {}},
                        {pn::kInterfaceSubslot, 0, 0x8000, 0, 0, {}},
                        {pn::kPortSubslot, 0, 0x8001, 0, 0, {}}}});
  d.modules.push_back({1, 0x00000010, {{1, 0, 0x00000011, 4, 4, {}}}});
  return d;
}

// The ExpectedSubmoduleBlockReq a controller builds from a description.
inline std::vector<pn::ExpectedSubmoduleBlockReq> expected_from(const pn::DeviceDescription& d) {
  std::vector<pn::ExpectedSubmoduleBlockReq> out;
  for (const auto& m : d.modules) {
    pn::ExpectedSubmoduleBlockReq b;
    pn::ExpectedModule em;
    em.api = m.submodules.empty() ? 0 : m.submodules.front().api;
    em.slot = m.slot;
    em.module_ident = m.module_ident;
    for (const auto& s : m.submodules) {
      pn::ExpectedSubmodule es;
      es.subslot = s.subslot;
      es.submodule_ident = s.submodule_ident;
      es.input_length = s.input_length;
      es.output_length = s.output_length;
      em.submodules.push_back(es);
    }
    b.modules.push_back(em);
    out.push_back(b);
  }
  return out;
}

inline const pn::Uuid kArUuid{0x11223344, 0x5566, 0x7788, {1, 2, 3, 4, 5, 6, 7, 8}};

// A valid Connect for `d` from a controller with MAC `ctl`: AR (session 7,
// initiator "plc"), input CR FrameID 0xC001 and output CR (device's choice)
// at 1 ms, the default AlarmCR, the expected submodules of `d`.
inline pn::ConnectRequest make_connect_request(const pn::DeviceDescription& d, const pn::Mac& ctl) {
  pn::ConnectRequest r;
  r.ar.ar_uuid = kArUuid;
  r.ar.session_key = 7;
  r.ar.cm_initiator_mac = ctl;
  r.ar.cm_initiator_object_uuid = pn::pnio_object_uuid(1, 0x0001, 0x0FFF);
  r.ar.station_name = "plc";
  r.expected = expected_from(d);
  pn::CyclicLayout layout;
  EXPECT_TRUE(pn::compute_layout(r.expected, layout));
  pn::IocrBlockReq in;
  in.iocr_type = pn::iocr::kTypeInput;
  in.iocr_reference = 1;
  in.frame_id = 0xC001;
  in.send_clock_factor = 32;
  in.reduction_ratio = 1;
  pn::apply_layout(layout.input, in);
  pn::IocrBlockReq out = in;
  out.iocr_type = pn::iocr::kTypeOutput;
  out.iocr_reference = 2;
  out.frame_id = 0xFFFF;
  pn::apply_layout(layout.output, out);
  r.iocrs = {in, out};
  return r;
}

class DeviceHarness : public ::testing::Test {
 public:
  static constexpr pn::Mac kCtlMac{0x02, 0, 0, 0, 0, 0x01};
  static constexpr pn::Mac kDevMac{0x02, 0, 0, 0, 0x12, 0x34};
  const pn::Ipv4 ctl_ip{0x0A000001};
  const pn::Ipv4 dev_ip{0x0A000002};

  void make_device(pn::DeviceDescription desc = echo_description(),
                   std::unique_ptr<io::DeviceModel> model = nullptr) {
    desc_ = desc;
    if (!model) {
      auto m = std::make_unique<EchoModel>();
      echo = m.get();
      model = std::move(m);
    }
    ctl_eth = hub.port(kCtlMac);
    dev_eth = hub.port(kDevMac);
    ctl_udp = net.port(ctl_ip, pn::kRpcUdpPort);
    pn::PnDeviceConfig cfg;
    cfg.description = desc;
    dev = std::make_unique<pn::PnDevice>(cfg, std::move(model), *dev_eth, [this](pn::Ipv4 ip) {
      return net.port(ip, pn::kRpcUdpPort);
    });
    dev->set_event_sink([this](const pn::PnDeviceEvent& e) { events.push_back(e); });
    run(microseconds(250));
  }

  // Advances virtual time in steps of `step`, polling the device each step.
  void run(nanoseconds d, nanoseconds step = microseconds(250)) {
    for (nanoseconds end = now + d; now < end;) {
      now += step;
      hub.set_time(now);
      net.set_time(now);
      dev->poll(now);
    }
  }

  // Every frame the controller port got since the last call.
  std::vector<std::vector<std::uint8_t>> controller_frames() {
    std::vector<std::vector<std::uint8_t>> out;
    std::array<std::uint8_t, pn::kMaxFrameLength> b{};
    for (int i = 0; i < 100000; ++i) {
      const std::size_t n = ctl_eth->receive(b, nanoseconds(0));
      if (n == 0) break;
      out.emplace_back(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
    }
    return out;
  }
  std::vector<std::vector<std::uint8_t>> frames_with_id(std::uint16_t id) {
    std::vector<std::vector<std::uint8_t>> out;
    for (auto& f : controller_frames()) {
      pn::PnFrameView v;
      if (pn::decode_pn_frame(f, v) && v.frame_id == id) out.push_back(std::move(f));
    }
    return out;
  }

  pn::ConnectRequest connect_request() const { return make_connect_request(desc_, kCtlMac); }

  // One RPC call from the controller; the device's answer (nullopt: none).
  struct Answer {
    pn::NdrResponse ndr;
    std::vector<std::uint8_t> datagram;
    std::vector<std::uint8_t> args;
  };
  std::optional<Answer> call(std::uint16_t opnum, const std::vector<std::uint8_t>& args,
                             pn::Ipv4 to = pn::Ipv4{0x0A000002}) {
    pn::RpcHeader h;
    h.object = pn::pnio_object_uuid(1, desc_.device_id, desc_.vendor_id);
    h.interface = pn::kPnioDeviceInterface;
    h.activity = pn::Uuid{0xAC000000U + seq_, 1, 2, {9, 9, 9, 9, 9, 9, 9, 9}};
    h.sequence_number = seq_++;
    h.opnum = opnum;
    const auto dgram = pn::encode_rpc(h, pn::encode_ndr_request(pn::rpc::kMaxArgs, args));
    ctl_udp->send_to(to, pn::kRpcUdpPort, dgram);
    for (int i = 0; i < 40; ++i) {
      run(microseconds(250));
      std::array<std::uint8_t, pn::kMaxDatagram> b{};
      pn::Ipv4 from;
      std::uint16_t port = 0;
      for (std::size_t n; (n = ctl_udp->receive_from(b, from, port, nanoseconds(0))) != 0;) {
        pn::RpcPdu pdu;
        if (!pn::decode_rpc(std::span<const std::uint8_t>(b.data(), n), pdu)) continue;
        if (pdu.header.packet_type == pn::rpc::kRequest) {
          pending_requests.emplace_back(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
          continue;
        }
        Answer a;
        a.datagram.assign(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
        pn::RpcPdu p2;
        EXPECT_TRUE(pn::decode_rpc(a.datagram, p2));
        EXPECT_TRUE(pn::decode_ndr_response(p2.body, p2.header.little_endian, a.ndr));
        a.args.assign(a.ndr.args.begin(), a.ndr.args.end());
        a.ndr.args = a.args;
        return a;
      }
    }
    return std::nullopt;
  }

  // Requests the device sent to the controller's RPC port (ApplicationReady).
  std::vector<std::vector<std::uint8_t>> device_requests() {
    std::array<std::uint8_t, pn::kMaxDatagram> b{};
    pn::Ipv4 from;
    std::uint16_t port = 0;
    for (std::size_t n; (n = ctl_udp->receive_from(b, from, port, nanoseconds(0))) != 0;)
      pending_requests.emplace_back(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
    auto out = std::move(pending_requests);
    pending_requests.clear();
    return out;
  }

  // Connect with `req`; returns the PNIO status (and the response).
  pn::PnioStatus connect(const pn::ConnectRequest& req, pn::ConnectResponse* res = nullptr) {
    const auto a = call(pn::rpc::kOpConnect, pn::encode_connect_request(req));
    EXPECT_TRUE(a.has_value());
    if (!a) return pn::PnioStatus::from(0xFFFFFFFF);
    if (a->ndr.status.ok()) {
      pn::ConnectResponse r;
      EXPECT_TRUE(pn::decode_connect_response(a->args, r));
      for (const auto& c : r.iocrs)
        if (c.iocr_type == pn::iocr::kTypeOutput) out_frame_id = c.frame_id;
      if (res) *res = r;
    }
    return a->ndr.status;
  }

  pn::PnioStatus prm_end() {
    pn::ControlBlock c;
    c.block_type = pn::block::kPrmEndReq;
    c.ar_uuid = kArUuid;
    c.session_key = 7;
    c.command = pn::control::kPrmEnd;
    const auto a = call(pn::rpc::kOpControl, pn::encode_control(c));
    EXPECT_TRUE(a.has_value());
    return a ? a->ndr.status : pn::PnioStatus::from(0xFFFFFFFF);
  }

  // Answers the device's ApplicationReady the way p-net expects (0x8112,
  // DONE); returns how many the device had sent.
  int answer_app_ready() {
    int n = 0;
    for (const auto& d : device_requests()) {
      pn::RpcPdu pdu;
      if (!pn::decode_rpc(d, pdu) || pdu.header.opnum != pn::rpc::kOpControl) continue;
      pn::NdrRequest ndr;
      pn::ControlBlock c;
      if (!pn::decode_ndr_request(pdu.body, pdu.header.little_endian, ndr) ||
          !pn::decode_control(ndr.args, c) || c.block_type != pn::block::kApplicationReadyReq)
        continue;
      ++n;
      const auto body = pn::encode_ndr_response({}, ndr.args_maximum,
                                                pn::encode_control(pn::control_response_for(c)));
      ctl_udp->send_to(dev_ip, pn::kRpcUdpPort,
                       pn::encode_rpc(pn::response_header_for(pdu.header), body));
    }
    return n;
  }

  // One controller output frame: the IO submodule's bytes with IOPS good.
  std::vector<std::uint8_t> output_frame(std::span<const std::uint8_t> data, std::uint16_t counter,
                                         std::uint8_t data_status = pn::data_status::kGood,
                                         std::uint8_t transfer = 0, pn::Mac src = kCtlMac) {
    pn::ConnectRequest req = connect_request();
    pn::IocrLayout layout;
    EXPECT_TRUE(pn::layout_from_iocr(req.iocrs[1], req.expected, layout));
    std::vector<std::uint8_t> c_sdu(layout.c_sdu_length, 0);
    for (const auto& o : layout.data) pn::put_io_data(c_sdu, o, data, pn::iocr::kIoxsGood);
    for (const auto& s : layout.iocs) c_sdu[s.offset] = pn::iocr::kIoxsGood;
    pn::CyclicHeader h;
    h.dst = kDevMac;
    h.src = src;
    h.frame_id = out_frame_id;
    h.cycle_counter = counter;
    h.data_status = data_status;
    h.transfer_status = transfer;
    std::vector<std::uint8_t> f(pn::kMaxFrameLength);
    f.resize(pn::encode_cyclic(f, h, c_sdu));
    return f;
  }
  void send_output(std::span<const std::uint8_t> data) {
    counter_ = static_cast<std::uint16_t>(counter_ + 32);
    ctl_eth->send(output_frame(data, counter_));
  }

  // Connect, PrmEnd, ApplicationReady answered, first output frame: the
  // device in data exchange.
  void bring_up() {
    ASSERT_TRUE(connect(connect_request()).ok());
    ASSERT_TRUE(prm_end().ok());
    run(milliseconds(1));
    ASSERT_EQ(answer_app_ready(), 1);
    const std::array<std::uint8_t, 4> d{1, 2, 3, 4};
    send_output(d);
    run(milliseconds(1));
    ASSERT_EQ(dev->state(), pn::PnDeviceState::DataExchange);
  }

  bool saw(pn::PnDeviceEvent::Kind k) const {
    for (const auto& e : events)
      if (e.kind == k) return true;
    return false;
  }

  pn::MemoryEthernet hub;
  pn::MemoryUdp net;
  std::unique_ptr<pn::EthernetPort> ctl_eth, dev_eth;
  std::unique_ptr<pn::UdpPort> ctl_udp;
  std::unique_ptr<pn::PnDevice> dev;
  EchoModel* echo = nullptr;
  std::vector<pn::PnDeviceEvent> events;
  std::vector<std::vector<std::uint8_t>> pending_requests;
  nanoseconds now{0};
  std::uint16_t out_frame_id = 0;
  std::uint16_t counter_ = 0;
  std::uint32_t seq_ = 1;
  pn::DeviceDescription desc_;
};

}  // namespace pn_test

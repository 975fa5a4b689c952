// PnDevice accepts what a p-net device accepts (issue 21 point 3;
// connect_check.hpp, README "Connect checks"). The Connects real
// controllers send that p-net's pf_cmdev.c lets through: profinet-py's
// (one IO submodule, NumberOfIOCS 0 in both IOCRs, no slot 0), hand-built
// here byte by byte as its rpc.py builds it, against the echo model and
// the NORD model; a Siemens-style RT_CLASS_2 Connect in advanced start-up
// with the expected submodules before the AlarmCR block, as p-net's own
// test_cmrpc.cpp holds; and one row per further acceptance case found when
// comparing connect_check.cpp with pf_cmdev.c, each with the warning that
// names the IEC 61158-6-10 clause p-net does not keep.
#include <functional>

#include "plc/fb/safety/f_parameters.hpp"
#include "plc/profinet/description/builtin_descriptions.hpp"
#include "plc/profinet/device/connect_check.hpp"
#include "test_device_harness.hpp"

namespace pn_test {
namespace {

// Big-endian bytes, written without our block encoders.
struct Bytes {
  std::vector<std::uint8_t> b;
  void u8(std::uint8_t v) { b.push_back(v); }
  void u16(std::uint16_t v) {
    u8(static_cast<std::uint8_t>(v >> 8));
    u8(static_cast<std::uint8_t>(v));
  }
  void u32(std::uint32_t v) {
    u16(static_cast<std::uint16_t>(v >> 16));
    u16(static_cast<std::uint16_t>(v));
  }
  void uuid(const pn::Uuid& u) {
    u32(u.data1);
    u16(u.data2);
    u16(u.data3);
    for (auto x : u.data4) u8(x);
  }
  void mac(const pn::Mac& m) {
    for (auto x : m) u8(x);
  }
  // Block header; end() fills in BlockLength (from BlockVersionHigh on).
  std::size_t begin(std::uint16_t type) {
    const std::size_t at = b.size();
    u16(type);
    u16(0);
    u8(1);
    u8(0);
    return at;
  }
  void end(std::size_t at) {
    const std::size_t len = b.size() - at - 4;
    b[at + 2] = static_cast<std::uint8_t>(len >> 8);
    b[at + 3] = static_cast<std::uint8_t>(len);
  }
};

// What profinet-py (f0rw4rd/profinet-py, rpc.py connect() with an
// IOCRSetup of one IOSlot) sends: ARBlockReq (IOCARSingle, properties
// 0x11, timeout 100, station "tp"), input IOCR (FrameID 0xC000 + ref 1)
// and output IOCR (0x8000 + ref 2) at SendClockFactor 32 / ReductionRatio
// 32, WatchdogFactor and DataHoldFactor 6, each with the one IO data object
// at offset 0 and NumberOfIOCS 0, DataLength max(40, data + IOPS); the
// AlarmCR block; one ExpectedSubmoduleBlockReq with the IO submodule only
// (Type IO, an input and an output DataDescription). Session key 7 and
// our AR UUID, so that the harness's PrmEnd and Release match.
std::vector<std::uint8_t> profinet_py_connect(const pn::Mac& ctl, std::uint16_t slot,
                                              std::uint16_t subslot, std::uint32_t module_ident,
                                              std::uint32_t submodule_ident, std::uint16_t in_len,
                                              std::uint16_t out_len) {
  Bytes x;
  std::size_t at = x.begin(pn::block::kArBlockReq);
  x.u16(0x0001);
  x.uuid(kArUuid);
  x.u16(7);
  x.mac(ctl);
  x.uuid(pn::Uuid{0xDEA00000, 0x6C97, 0x11D1, {0x82, 0x71, 0x00, 0x01, 0x76, 0x54, 0x32, 0x10}});
  x.u32(0x00000011);
  x.u16(100);
  x.u16(0x8892);
  x.u16(2);
  x.u8('t');
  x.u8('p');
  x.end(at);
  for (std::uint16_t type : {1, 2}) {
    const std::uint16_t len = type == 1 ? in_len : out_len;
    at = x.begin(pn::block::kIocrBlockReq);
    x.u16(type);
    x.u16(type);  // IOCRReference
    x.u16(0x8892);
    x.u32(0x00000001);  // RT_CLASS_1
    x.u16(static_cast<std::uint16_t>(std::max(40, len + 1)));
    x.u16(static_cast<std::uint16_t>(type == 1 ? 0xC000 + type : 0x8000 + type));
    x.u16(32);          // SendClockFactor
    x.u16(32);          // ReductionRatio
    x.u16(1);           // Phase
    x.u16(0);           // Sequence
    x.u32(0xFFFFFFFF);  // FrameSendOffset
    x.u16(6);           // WatchdogFactor
    x.u16(6);           // DataHoldFactor
    x.u16(0xC000);      // IOCRTagHeader
    x.mac({});          // IOCRMulticastMACAdd
    x.u16(1);           // NumberOfAPIs
    x.u32(0);           // API
    x.u16(1);           // NumberOfIODataObjects
    x.u16(slot);
    x.u16(subslot);
    x.u16(0);  // IODataObjectFrameOffset
    x.u16(0);  // NumberOfIOCS
    x.end(at);
  }
  at = x.begin(pn::block::kAlarmCrBlockReq);
  x.u16(0x0001);
  x.u16(0x8892);
  x.u32(0);
  x.u16(1);
  x.u16(3);
  x.u16(1);
  x.u16(200);
  x.u16(0xC000);
  x.u16(0xA000);
  x.end(at);
  at = x.begin(pn::block::kExpectedSubmoduleBlockReq);
  x.u16(1);  // NumberOfAPIs
  x.u32(0);
  x.u16(slot);
  x.u32(module_ident);
  x.u16(0);
  x.u16(1);  // NumberOfSubmodules
  x.u16(subslot);
  x.u32(submodule_ident);
  x.u16(0x0003);  // Type IO
  for (std::uint16_t dir : {1, 2}) {
    x.u16(dir);
    x.u16(dir == 1 ? in_len : out_len);
    x.u8(1);
    x.u8(1);
  }
  x.end(at);
  return x.b;
}

// The helpers; DeviceConnectPnet hosts the echo model, DeviceConnectPnetNord
// the NORD model.
class PnetConnectHarness : public DeviceHarness {
 protected:
  // Connects with raw args; the status and the decoded response.
  pn::PnioStatus connect_raw(const std::vector<std::uint8_t>& args, pn::ConnectResponse& res) {
    const auto a = call(pn::rpc::kOpConnect, args);
    EXPECT_TRUE(a.has_value());
    if (!a) return pn::PnioStatus::from(0xFFFFFFFF);
    if (a->ndr.status.ok()) {
      EXPECT_TRUE(pn::decode_connect_response(a->args, res));
    }
    return a->ndr.status;
  }
  std::uint16_t frame_id_of(const pn::ConnectResponse& res, std::uint16_t type) {
    for (const auto& c : res.iocrs)
      if (c.iocr_type == type) return c.frame_id;
    return 0;
  }
  std::vector<std::string> warnings() const {
    std::vector<std::string> out;
    for (const auto& e : events)
      if (e.kind == pn::PnDeviceEvent::Kind::Warning) out.push_back(e.text);
    return out;
  }
  // One controller frame: `data` at offset 0 with IOPS good after it, a
  // C_SDU of `c_sdu` bytes, nothing else (profinet-py's output frame).
  void send_plain_output(std::uint16_t frame_id, std::span<const std::uint8_t> data,
                         std::size_t c_sdu) {
    std::vector<std::uint8_t> sdu(c_sdu, 0);
    std::copy(data.begin(), data.end(), sdu.begin());
    sdu[data.size()] = pn::iocr::kIoxsGood;
    counter_ = static_cast<std::uint16_t>(counter_ + 1024);
    pn::CyclicHeader h;
    h.dst = kDevMac;
    h.src = kCtlMac;
    h.frame_id = frame_id;
    h.cycle_counter = counter_;
    std::vector<std::uint8_t> f(pn::kMaxFrameLength);
    f.resize(pn::encode_cyclic(f, h, sdu));
    ctl_eth->send(f);
  }
  // PrmEnd, ApplicationReady answered, one output frame: data exchange.
  void start_exchange(std::uint16_t out_frame, std::span<const std::uint8_t> data,
                      std::size_t c_sdu) {
    ASSERT_TRUE(prm_end().ok());
    run(milliseconds(1));
    ASSERT_EQ(answer_app_ready(), 1);
    send_plain_output(out_frame, data, c_sdu);
    run(milliseconds(1));
    ASSERT_EQ(dev->state(), pn::PnDeviceState::DataExchange);
  }
  pn::PnioStatus release() {
    pn::ControlBlock c;
    c.block_type = pn::block::kReleaseReq;
    c.ar_uuid = kArUuid;
    c.session_key = 7;
    c.command = pn::control::kRelease;
    const auto a = call(pn::rpc::kOpRelease, pn::encode_control(c));
    EXPECT_TRUE(a.has_value());
    return a ? a->ndr.status : pn::PnioStatus::from(0xFFFFFFFF);
  }
};

class DeviceConnectPnet : public PnetConnectHarness {
 protected:
  void SetUp() override { make_device(); }
};
class DeviceConnectPnetNord : public PnetConnectHarness {};

bool any_contains(const std::vector<std::string>& lines, const std::string& what) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& l) { return l.find(what) != std::string::npos; });
}

// Before: refused DB 81 02 18 (the device's layout wanted an IOCS of every
// submodule). p-net accepts it; so do we, warn about the missing IOCS
// (IEC 61158-6-10 IOCRBlockReq), keep the controller's output FrameID
// 0x8002 as p-net does, echo the data, take records and the Release.
TEST_F(DeviceConnectPnet, ProfinetPyConnectWithoutIocsEchoesRecordsAndReleases) {
  pn::ConnectResponse res;
  const auto args = profinet_py_connect(kCtlMac, 1, 1, 0x10, 0x11, 4, 4);
  ASSERT_FALSE(pn::check_connect_blocks(args).has_value());
  ASSERT_EQ(connect_raw(args, res).value(), 0u);
  EXPECT_EQ(frame_id_of(res, pn::iocr::kTypeInput), 0xC001);
  EXPECT_EQ(frame_id_of(res, pn::iocr::kTypeOutput), 0x8002);
  EXPECT_FALSE(res.module_diff.has_value());
  const auto w = warnings();
  ASSERT_EQ(w.size(), 2u);
  EXPECT_TRUE(any_contains(w, "input CR lists no IOCS for API 0x0 slot 1 subslot 0x0001"));
  EXPECT_TRUE(any_contains(w, "output CR lists no IOCS for API 0x0 slot 1 subslot 0x0001"));
  for (const auto& l : w) EXPECT_NE(l.find("IEC 61158-6-10 IOCRBlockReq"), std::string::npos);
  // pndevsim prints each as "pndevsim: NAME: warning: ...".
  const auto ev = std::find_if(events.begin(), events.end(), [](const auto& e) {
    return e.kind == pn::PnDeviceEvent::Kind::Warning;
  });
  ASSERT_NE(ev, events.end());
  EXPECT_EQ(pn::describe(*ev).rfind("warning: input CR lists no IOCS", 0), 0u) << pn::describe(*ev);

  // A record before PrmEnd, read back.
  const pn::RecordWrite rec{0, 1, 1, 0x0042, {9, 8, 7}};
  const auto wr = call(pn::rpc::kOpWrite, pn::encode_write_request(1, kArUuid, std::span(&rec, 1)));
  ASSERT_TRUE(wr.has_value());
  EXPECT_TRUE(wr->ndr.status.ok());
  ASSERT_EQ(echo->records[0x0042], (std::vector<std::uint8_t>{9, 8, 7}));

  const std::array<std::uint8_t, 4> out{0x01, 0x02, 0x03, 0x04};
  start_exchange(0x8002, out, 40);
  controller_frames();
  send_plain_output(0x8002, out, 40);
  run(milliseconds(40));  // input frames every 32 ms
  const auto in = frames_with_id(0xC001);
  ASSERT_FALSE(in.empty());
  pn::CyclicView v;
  ASSERT_TRUE(pn::decode_cyclic(in.back(), 40, v));
  EXPECT_EQ(v.header.dst, kCtlMac);
  EXPECT_EQ(v.c_sdu[0], 0xFE);  // the echo model: outputs XOR 0xFF
  EXPECT_EQ(v.c_sdu[3], 0xFB);
  EXPECT_EQ(v.c_sdu[4], pn::iocr::kIoxsGood);                          // IOPS right after the data
  for (std::size_t i = 5; i < 40; ++i) EXPECT_EQ(v.c_sdu[i], 0) << i;  // no IOCS was asked for

  EXPECT_TRUE(release().ok());
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Idle);
  EXPECT_TRUE(saw(pn::PnDeviceEvent::Kind::Released));
}

// The case: pndevsim hosting the NORD model refused profinet-py's
// Connect with DB 81 02 18. Accepted now, the F-parameters go in by
// record, data exchange runs, the Release is answered.
TEST_F(DeviceConnectPnetNord, ProfinetPyConnectToTheNordModel) {
  io::ModelParams p;
  p.set("dip_address", "1");
  p.set("p802_3", "1");
  auto desc = pn::builtin_description("nord_profisafe", p);
  desc.station_name = "safety";
  desc.ip = dev_ip;
  const io::DeviceModelFactory* f = io::DeviceModelRegistry::instance().find("nord_profisafe");
  ASSERT_NE(f, nullptr);
  make_device(desc, (*f)(p));
  const auto* io_sub = desc.io_submodule();
  const auto* io_mod = desc.module_of(io_sub);
  ASSERT_EQ(io_sub->input_length, 8);
  const auto args =
      profinet_py_connect(kCtlMac, io_mod->slot, io_sub->subslot, io_mod->module_ident,
                          io_sub->submodule_ident, io_sub->input_length, io_sub->output_length);
  pn::ConnectResponse res;
  ASSERT_EQ(connect_raw(args, res).value(), 0u);
  EXPECT_FALSE(res.module_diff.has_value());
  EXPECT_EQ(warnings().size(), 2u);

  plc::safety::FParameters fp;
  fp.dest_add = 1;
  std::array<std::uint8_t, plc::safety::kFParamBlockSize> block{};
  plc::safety::encode(fp, block);
  const pn::RecordWrite rec{io_sub->api,
                            io_mod->slot,
                            io_sub->subslot,
                            plc::safety::kFParamRecordIndex,
                            {block.begin(), block.end()}};
  const auto wr = call(pn::rpc::kOpWrite, pn::encode_write_request(1, kArUuid, std::span(&rec, 1)));
  ASSERT_TRUE(wr.has_value());
  EXPECT_TRUE(wr->ndr.status.ok()) << std::hex << wr->ndr.status.value();

  const std::array<std::uint8_t, 8> out{};
  start_exchange(frame_id_of(res, pn::iocr::kTypeOutput), out, 40);
  controller_frames();
  run(milliseconds(70));
  const auto in = frames_with_id(0xC001);
  ASSERT_GE(in.size(), 2u);
  pn::CyclicView v;
  ASSERT_TRUE(pn::decode_cyclic(in.back(), 40, v));
  EXPECT_EQ(v.c_sdu[8], pn::iocr::kIoxsGood);
  EXPECT_TRUE(release().ok());
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Idle);
}

// A Siemens controller's Connect as p-net's test_cmrpc.cpp keeps it
// (read with tshark): advanced start-up (ARProperties 0x40000011),
// RT_CLASS_2 in both IOCRs, input FrameID 0x8000, output 0xFFFF, the
// ExpectedSubmoduleBlockReqs before the AlarmCRBlockReq. Before: refused
// DB 81 02 07 ("RT_CLASS_1 only"). p-net answers the output FrameID with
// the first free RT_CLASS_2 one, 0x8001, and runs the frames as RT_CLASS_1.
TEST_F(DeviceConnectPnet, SiemensStyleRtClass2AdvancedStartupRuns) {
  auto req = connect_request();
  req.ar.ar_properties |= 0x40000000U;
  for (auto& c : req.iocrs) c.iocr_properties = 2;
  req.iocrs[0].frame_id = 0x8000;
  req.iocrs[1].frame_id = 0xFFFF;
  req.iocrs[0].reduction_ratio = req.iocrs[1].reduction_ratio = 2;
  std::vector<std::uint8_t> args;
  pn::ByteBuilder b(args);
  pn::encode_block(b, req.ar);
  for (const auto& c : req.iocrs) pn::encode_block(b, c);
  for (const auto& e : req.expected) pn::encode_block(b, e);
  pn::encode_block(b, req.alarm_cr);
  pn::ConnectResponse res;
  ASSERT_EQ(connect_raw(args, res).value(), 0u);
  EXPECT_EQ(frame_id_of(res, pn::iocr::kTypeInput), 0x8000);
  out_frame_id = frame_id_of(res, pn::iocr::kTypeOutput);
  EXPECT_EQ(out_frame_id, 0x8001);
  EXPECT_TRUE(warnings().empty());
  ASSERT_TRUE(prm_end().ok());
  run(milliseconds(1));
  ASSERT_EQ(answer_app_ready(), 1);
  const std::array<std::uint8_t, 4> d{5, 6, 7, 8};
  send_output(d);
  run(milliseconds(1));
  EXPECT_EQ(dev->state(), pn::PnDeviceState::DataExchange);
  controller_frames();
  run(milliseconds(4));
  EXPECT_EQ(echo->last_outputs, (std::vector<std::uint8_t>{5, 6, 7, 8}));
  EXPECT_GE(frames_with_id(0x8000).size(), 2u);  // every 2 ms
}

// p-net's own test Connect (test_cmrpc.cpp connect_req, "rt-labs-demo"):
// RT_CLASS_2 in advanced start-up with the output FrameID proposed
// (0x8000) and the input on 0x8001: the proposal is kept.
TEST_F(DeviceConnectPnet, RtClass2OutputFrameIdProposalIsKept) {
  auto req = connect_request();
  req.ar.ar_properties |= 0x40000000U;
  for (auto& c : req.iocrs) c.iocr_properties = 2;
  req.iocrs[0].frame_id = 0x8001;
  req.iocrs[1].frame_id = 0x8000;
  req.ar.station_name = "rt-labs-demo";
  pn::ConnectResponse res;
  ASSERT_TRUE(connect(req, &res).ok());
  EXPECT_EQ(frame_id_of(res, pn::iocr::kTypeOutput), 0x8000);
}

// One row per p-net acceptance case: a mutation of a valid Connect that
// p-net accepts, and the warning we give (empty: by the book).
struct Accepted {
  const char* name;
  std::function<void(pn::ConnectRequest&)> mutate;
  const char* warning;
};
void PrintTo(const Accepted& a, std::ostream* os) { *os << a.name; }

pn::ExpectedSubmodule& io_submodule(pn::ConnectRequest& q) {
  return q.expected[1].modules[0].submodules[0];
}

const std::vector<Accepted>& accepted() {
  static const std::vector<Accepted> r = {
      // pf_cmdev_check_iocr_apis asks no IOCS at all (profinet-py).
      {"NoIocsInEitherIocr",
       [](auto& q) {
         for (auto& c : q.iocrs)
           for (auto& a : c.apis) a.iocs.clear();
       },
       "lists no IOCS for"},
      // ... nor an IO data object for every submodule: the DAP submodules
      // named only by their IOCS in the output CR.
      {"DapSubmodulesOnlyAsIocs",
       [](auto& q) {
         auto& d = q.iocrs[0].apis[0].data_objects;
         d.erase(std::remove_if(d.begin(), d.end(), [](const auto& e) { return e.slot == 0; }),
                 d.end());
       },
       "lists no IO data object for API 0x0 slot 0 subslot 0x0001"},
      // pf_cmdev_check_iocr_overlap compares a submodule with the others only.
      {"IocsOnItsOwnData",
       [](auto& q) {
         auto& a = q.iocrs[0].apis[0];
         for (auto& s : a.iocs)
           for (const auto& d : a.data_objects)
             if (s.slot == d.slot && s.subslot == d.subslot) s.frame_offset = d.frame_offset;
       },
       "lies on its own data or IOPS"},
      // p-net reads IOCRVLANID as bits 0..10.
      {"IocrTagHeaderVlanBit11", [](auto& q) { q.iocrs[0].iocr_tag_header = 0xC800; },
       "VLAN ID bit 11"},
      // 263 x 512 x 32 x 1000 wraps in 32 bits to 14024704 (/32 < 1920000).
      {"DataHoldTimeWrapsInPnetsArithmetic",
       [](auto& q) {
         q.iocrs[1].reduction_ratio = 512;
         q.iocrs[1].data_hold_factor = 263;
       },
       "data hold time 134656000 us"},
      {"RtClass2Legacy",
       [](auto& q) {
         for (auto& c : q.iocrs) c.iocr_properties = 2;
         q.iocrs[0].frame_id = 0x8001;
       },
       ""},
      // DataLength is checked for RT_CLASS_1 and UDP only.
      {"RtClass2DataLength30",
       [](auto& q) {
         for (auto& c : q.iocrs) {
           c.iocr_properties = 2;
           c.data_length = 30;
         }
         q.iocrs[0].frame_id = 0x8001;
       },
       "DataLength 30 is below 40"},
      {"RtClassUdp",
       [](auto& q) {
         for (auto& c : q.iocrs) {
           c.iocr_properties = 4;
           c.lt = 0x0800;
         }
         q.ar.cm_initiator_mac = {};
       },
       "RT_CLASS_UDP"},
      {"RtClassStream",
       [](auto& q) {
         for (auto& c : q.iocrs) c.iocr_properties = 5;
       },
       "RT_CLASS_STREAM"},
      {"ArRpcBlockWithServerPort", [](auto& q) { q.ar_rpc = pn::ArRpcBlockReq{0x8894}; }, ""},
      // Type INPUT with an input description of length 0 (our decoder
      // refused a Type that disagreed with the lengths).
      {"InputTypeWithoutInputData",
       [](auto& q) {
         auto& s = q.expected[0].modules[0].submodules[0];
         s.wire_type = pn::submodule::kTypeInput;
         s.descriptions = {{pn::submodule::kDataInput, 0, 1, 1}};
       },
       ""},
      {"SharedInputOnIoSubmodule",
       [](auto& q) { io_submodule(q).properties |= pn::submodule::kSharedInput; }, ""},
      // DiscardIOXS on an IO submodule: no bytes travel for it.
      {"DiscardIoxsOnIoSubmodule",
       [](auto& q) { io_submodule(q).properties |= pn::submodule::kDiscardIoxs; }, ""},
      // The output FrameID proposal outside the RT class's range is kept.
      {"OutputFrameIdOfAnotherRange", [](auto& q) { q.iocrs[1].frame_id = 0x8002; }, ""},
  };
  return r;
}

class DeviceConnectAccepted : public DeviceHarness, public ::testing::WithParamInterface<Accepted> {
 protected:
  void SetUp() override { make_device(); }
};

TEST_P(DeviceConnectAccepted, AcceptedAsPnetAcceptsIt) {
  auto req = connect_request();
  GetParam().mutate(req);
  EXPECT_FALSE(pn::check_connect(req, desc_).has_value());
  const auto args = pn::encode_connect_request(req);
  EXPECT_FALSE(pn::check_connect_blocks(args).has_value());
  pn::ConnectResponse res;
  ASSERT_EQ(connect(req, &res).value(), 0u);
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Parameterizing);
  const auto w = pn::connect_warnings(req);
  const std::string want = GetParam().warning;
  if (want.empty()) {
    EXPECT_TRUE(w.empty()) << w.front();
  } else {
    EXPECT_TRUE(any_contains(w, want)) << (w.empty() ? "no warning" : w.front());
    EXPECT_TRUE(any_contains(w, "IEC 61158-6-10"));
    EXPECT_TRUE(saw(pn::PnDeviceEvent::Kind::Warning));
  }
}

INSTANTIATE_TEST_SUITE_P(PnetAcceptanceCases, DeviceConnectAccepted,
                         ::testing::ValuesIn(accepted()),
                         [](const auto& info) { return std::string(info.param.name); });

// A valid Connect by the book gives no warning.
TEST_F(DeviceConnectPnet, ConnectByTheBookHasNoWarning) {
  EXPECT_TRUE(pn::connect_warnings(connect_request()).empty());
  ASSERT_TRUE(connect(connect_request()).ok());
  EXPECT_TRUE(warnings().empty());
}

// An odd CMInitiatorStationName travels unpadded (p-net wants BlockLength
// 54 + the name's length exactly) and is accepted.
TEST_F(DeviceConnectPnet, OddInitiatorStationNameIsAccepted) {
  auto req = connect_request();
  req.ar.station_name = "rt-labs-dev";
  const auto args = pn::encode_connect_request(req);
  ASSERT_EQ(args[2] << 8 | args[3], 54 + 11);
  EXPECT_TRUE(connect(req).ok());
}

}  // namespace
}  // namespace pn_test

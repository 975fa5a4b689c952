// PnDevice: the Connect checks of p-net's pf_cmdev.c (fieldbus-masters.md
// §1 item 2), each refused with p-net's PNIO status 0xDB 0x81 code1 code2
// (code1: 0x01 ARBlockReq, 0x02 IOCRBlockReq, 0x03 ExpectedSubmoduleBlockReq,
// 0x04 AlarmCRBlockReq, 0x40 CMRPC; code2: the field, p-net's numbering),
// the accepted Connect (IEC 61158-6-10 IODConnectRes) and the ModuleDiffBlock.
#include <functional>

#include "plc/profinet/device/connect_check.hpp"
#include "test_device_harness.hpp"

namespace pn_test {
namespace {

class DeviceConnect : public DeviceHarness {
 protected:
  void SetUp() override { make_device(); }
};

TEST_F(DeviceConnect, AcceptedConnectAnswersArIocrAlarmCrAndStartsOutputFramesAtOnce) {
  pn::ConnectResponse res;
  ASSERT_TRUE(connect(connect_request(), &res).ok());
  EXPECT_EQ(res.ar.ar_uuid, kArUuid);
  EXPECT_EQ(res.ar.session_key, 7);
  EXPECT_EQ(res.ar.cm_responder_mac, kDevMac);
  ASSERT_EQ(res.iocrs.size(), 2u);
  EXPECT_EQ(res.iocrs[0].frame_id, 0xC001);  // input: the controller's choice
  EXPECT_TRUE(pn::is_rt_class1(res.iocrs[1].frame_id));
  EXPECT_NE(res.iocrs[1].frame_id, 0xC001);
  EXPECT_FALSE(res.module_diff.has_value());
  ASSERT_TRUE(res.ar_server.has_value());
  EXPECT_EQ(res.ar_server->station_name, "echo-1");
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Parameterizing);
  EXPECT_TRUE(saw(pn::PnDeviceEvent::Kind::Connected));
  // Input frames (FrameID 0xC001) flow before PrmEnd, one per 1 ms, with the
  // IO submodule's IOPS good (profinet-py issue 15 in fieldbus-masters.md §1).
  controller_frames();
  run(milliseconds(5));
  const auto frames = frames_with_id(0xC001);
  EXPECT_GE(frames.size(), 4u);
  EXPECT_LE(frames.size(), 6u);
  ASSERT_FALSE(frames.empty());
  pn::CyclicView v;
  pn::IocrLayout in;
  const auto req = connect_request();
  ASSERT_TRUE(pn::layout_from_iocr(req.iocrs[0], req.expected, in));
  ASSERT_TRUE(pn::decode_cyclic(frames.back(), in.c_sdu_length, v));
  EXPECT_EQ(v.header.dst, kCtlMac);
  EXPECT_EQ(v.header.data_status, 0x35);
  for (const auto& o : in.data) EXPECT_EQ(pn::iops(v.c_sdu, o), 0x80);
}

TEST_F(DeviceConnect, RepeatedConnectOfTheSameArGetsTheSameAnswer) {
  ASSERT_TRUE(connect(connect_request()).ok());
  ASSERT_TRUE(connect(connect_request()).ok());
  EXPECT_EQ(dev->counters().connects_refused, 0u);
  // Another AR while one is up: no AR resources (CMRPC 0x04).
  auto other = connect_request();
  other.ar.ar_uuid.data1 ^= 1;
  EXPECT_EQ(connect(other), pn::connect_refusal(0x40, 0x04));
}

// One row per p-net check: a mutation of a valid request and the status.
struct Refusal {
  const char* name;
  std::function<void(pn::ConnectRequest&)> mutate;
  std::uint8_t code1, code2;
};

void PrintTo(const Refusal& r, std::ostream* os) { *os << r.name; }

const std::vector<Refusal>& refusals() {
  static const std::vector<Refusal> r = {
      // pf_cmdev_check_ar_param
      {"ArTypeNotIocarSingle", [](auto& q) { q.ar.ar_type = 0x0006; }, 0x01, 4},
      {"ArUuidNil", [](auto& q) { q.ar.ar_uuid = {}; }, 0x01, 5},
      {"InitiatorMacMulticast", [](auto& q) { q.ar.cm_initiator_mac[0] = 0x01; }, 0x01, 7},
      {"InitiatorObjectUuidNotPnio",
       [](auto& q) { q.ar.cm_initiator_object_uuid.data1 = 0x12345678; }, 0x01, 8},
      {"ArStateNotActive", [](auto& q) { q.ar.ar_properties &= ~0x7U; }, 0x01, 9},
      {"ExternalParameterServer", [](auto& q) { q.ar.ar_properties &= ~0x10U; }, 0x01, 9},
      {"ActivityTimeoutFactor0", [](auto& q) { q.ar.activity_timeout_factor = 0; }, 0x01, 10},
      {"ActivityTimeoutFactor1001", [](auto& q) { q.ar.activity_timeout_factor = 1001; }, 0x01, 10},
      {"InitiatorStationNameEmpty", [](auto& q) { q.ar.station_name.clear(); }, 0x01, 12},
      {"InitiatorStationNameNotVisible",
       [](auto& q) {
         q.ar.station_name =
             "pl\x01"
             "c";
       },
       0x01, 13},
      // pf_cmdev_check_iocr_param
      {"IocrTypeUnknown", [](auto& q) { q.iocrs[0].iocr_type = 7; }, 0x02, 4},
      {"IocrLtNotProfinet", [](auto& q) { q.iocrs[0].lt = 0x0800; }, 0x02, 6},
      // RT_CLASS_3 passes the RT class check; its input FrameID range is 0x0100..0x7FFF.
      {"IocrRtClass3InputFrameIdOfRtClass1", [](auto& q) { q.iocrs[0].iocr_properties = 3; }, 0x02,
       9},
      {"IocrRtClass6", [](auto& q) { q.iocrs[0].iocr_properties = 6; }, 0x02, 7},
      {"AdvancedStartupWithRtClass1", [](auto& q) { q.ar.ar_properties |= 0x40000000U; }, 0x02, 7},
      {"RtClass2InputFrameIdOfRtClass1", [](auto& q) { q.iocrs[0].iocr_properties = 2; }, 0x02, 9},
      {"RtClass2DataLength1441",
       [](auto& q) {
         q.iocrs[0].iocr_properties = 2;
         q.iocrs[0].frame_id = 0x8001;
         q.iocrs[0].data_length = 1441;
       },
       0x02, 8},
      {"RtClassUdpWithInitiatorMac",
       [](auto& q) {
         q.iocrs[0].iocr_properties = 4;
         q.iocrs[0].lt = 0x0800;
       },
       0x01, 7},
      {"RtClassUdpRtPortBelow0x400",
       [](auto& q) {
         q.iocrs[0].iocr_properties = 4;
         q.iocrs[0].lt = 0x0800;
         q.ar.cm_initiator_mac = {};
         q.ar.initiator_udp_rt_port = 0x03FF;
       },
       0x01, 11},
      {"IocrReservedBitsSet", [](auto& q) { q.iocrs[0].iocr_properties |= 0x10; }, 0x02, 7},
      {"IocrDataLength39", [](auto& q) { q.iocrs[0].data_length = 39; }, 0x02, 8},
      {"IocrDataLength1441", [](auto& q) { q.iocrs[0].data_length = 1441; }, 0x02, 8},
      {"InputFrameIdOutsideRtClass1", [](auto& q) { q.iocrs[0].frame_id = 0x8000; }, 0x02, 9},
      {"SendClockFactorNotPowerOfTwo", [](auto& q) { q.iocrs[0].send_clock_factor = 3; }, 0x02, 10},
      {"SendClockFactor256", [](auto& q) { q.iocrs[0].send_clock_factor = 256; }, 0x02, 10},
      {"ReductionRatio0", [](auto& q) { q.iocrs[0].reduction_ratio = 0; }, 0x02, 11},
      {"ReductionRatio513", [](auto& q) { q.iocrs[0].reduction_ratio = 513; }, 0x02, 11},
      {"BelowMinDeviceInterval", [](auto& q) { q.iocrs[0].send_clock_factor = 8; }, 0x02, 11},
      {"Phase0", [](auto& q) { q.iocrs[0].phase = 0; }, 0x02, 12},
      {"PhaseAboveReductionRatio", [](auto& q) { q.iocrs[0].phase = 2; }, 0x02, 12},
      {"FrameSendOffsetBeyondSendClock", [](auto& q) { q.iocrs[0].frame_send_offset = 1000000; },
       0x02, 14},
      {"DataHoldFactor0", [](auto& q) { q.iocrs[0].data_hold_factor = 0; }, 0x02, 16},
      {"DataHoldFactorAbove0x1E00", [](auto& q) { q.iocrs[0].data_hold_factor = 0x1E01; }, 0x02,
       16},
      {"DataHoldTimeAbove1920ms", [](auto& q) { q.iocrs[0].data_hold_factor = 1921; }, 0x02, 16},
      {"IocrVlanIdNot0", [](auto& q) { q.iocrs[0].iocr_tag_header = 0xC001; }, 0x02, 17},
      {"IocrPriorityNot6", [](auto& q) { q.iocrs[0].iocr_tag_header = 0xA000; }, 0x02, 17},
      {"IocrWithoutApis", [](auto& q) { q.iocrs[0].apis.clear(); }, 0x02, 19},
      // pf_cmdev_exp_modules_configure / _exp_submodule_configure
      {"ExpectedSlotMissingOnDevice", [](auto& q) { q.expected[1].modules[0].slot = 5; }, 0x03, 6},
      {"ExpectedSlotTwice", [](auto& q) { q.expected[1].modules[0].slot = 0; }, 0x03, 6},
      {"ExpectedModuleIdent0", [](auto& q) { q.expected[1].modules[0].module_ident = 0; }, 0x03, 7},
      {"ExpectedModuleWithoutSubmodules",
       [](auto& q) { q.expected[1].modules[0].submodules.clear(); }, 0x03, 9},
      {"ExpectedSubslotMissingOnDevice",
       [](auto& q) { q.expected[1].modules[0].submodules[0].subslot = 2; }, 0x03, 10},
      {"ExpectedSubmoduleLengthIops2",
       [](auto& q) { q.expected[1].modules[0].submodules[0].length_iops = 2; }, 0x03, 15},
      {"ExpectedSubmoduleLengthIocs2",
       [](auto& q) { q.expected[1].modules[0].submodules[0].length_iocs = 2; }, 0x03, 16},
      {"ExpectedSubmoduleInNoIocr",
       [](auto& q) {
         for (auto& c : q.iocrs) {
           auto& a = c.apis[0];
           std::erase_if(a.data_objects, [](const auto& e) { return e.slot == 1; });
           std::erase_if(a.iocs, [](const auto& e) { return e.slot == 1; });
         }
       },
       0x03, 10},
      {"ExpectedNoIoWithAnOutputDescription",
       [](auto& q) {
         auto& s = q.expected[0].modules[0].submodules[0];
         s.wire_type = pn::submodule::kTypeNoIo;
         s.descriptions = {{pn::submodule::kDataOutput, 0, 1, 1}};
       },
       0x03, 12},
      {"ExpectedIoSubmoduleWithOneDescription",
       [](auto& q) {
         auto& s = q.expected[1].modules[0].submodules[0];
         s.wire_type = pn::submodule::kTypeInputOutput;
         s.descriptions = {{pn::submodule::kDataInput, 4, 1, 1}};
       },
       0x03, 12},
      {"ExpectedSharedInputOnOutputSubmodule",
       [](auto& q) {
         auto& s = q.expected[1].modules[0].submodules[0];
         s.wire_type = pn::submodule::kTypeOutput;
         s.descriptions = {{pn::submodule::kDataOutput, 4, 1, 1}};
         s.properties = pn::submodule::kSharedInput;
       },
       0x03, 12},
      {"ExpectedReduceInputOnIoSubmodule",
       [](auto& q) {
         q.expected[1].modules[0].submodules[0].properties = pn::submodule::kReduceInputLength;
       },
       0x03, 12},
      {"ExpectedReduceOutputOnIoSubmodule",
       [](auto& q) {
         q.expected[1].modules[0].submodules[0].properties = pn::submodule::kReduceOutputLength;
       },
       0x03, 12},
      {"ExpectedDiscardIoxsOnNoIoSubmodule",
       [](auto& q) {
         q.expected[0].modules[0].submodules[0].properties = pn::submodule::kDiscardIoxs;
       },
       0x03, 12},
      {"ExpectedNoIoWithData",
       [](auto& q) {
         auto& s = q.expected[0].modules[0].submodules[0];
         s.wire_type = pn::submodule::kTypeNoIo;
         s.descriptions = {{pn::submodule::kDataInput, 2, 1, 1}};
       },
       0x03, 14},
      {"ExpectedDataLength1440",
       [](auto& q) { q.expected[1].modules[0].submodules[0].input_length = 1440; }, 0x03, 14},
      // pf_cmdev_check_iocr_apis
      {"IocrApiNotExpected", [](auto& q) { q.iocrs[0].apis[0].api = 0x3A00; }, 0x02, 20},
      {"IocrDataObjectTwice",
       [](auto& q) {
         q.iocrs[0].apis[0].data_objects.push_back(q.iocrs[0].apis[0].data_objects[0]);
       },
       0x02, 23},
      {"IocrDataObjectBeyondDataLength",
       [](auto& q) { q.iocrs[0].apis[0].data_objects.back().frame_offset = 39; }, 0x02, 24},
      {"IocrDataObjectsOverlap",
       [](auto& q) {
         auto& d = q.iocrs[0].apis[0].data_objects;
         d.back().frame_offset = d.front().frame_offset;
       },
       0x02, 24},
      {"IocrApiWithoutEntries",
       [](auto& q) {
         q.iocrs[0].apis[0].data_objects.clear();
         q.iocrs[0].apis[0].iocs.clear();
       },
       0x02, 21},
      {"IocrDataObjectOfUnexpectedSlot",
       [](auto& q) {
         q.iocrs[0].apis[0].data_objects.push_back({7, 1, 30});
       },
       0x02, 22},
      {"IocrDataObjectOfUnexpectedSubslot",
       [](auto& q) {
         q.iocrs[0].apis[0].data_objects.push_back({1, 9, 30});
       },
       0x02, 23},
      {"OutputIocrDataObjectOfNoIoSubmodule",
       [](auto& q) {
         q.iocrs[1].apis[0].data_objects.push_back({0, 1, 30});
       },
       0x02, 23},
      {"IocrIocsTwice",
       [](auto& q) { q.iocrs[0].apis[0].iocs.push_back(q.iocrs[0].apis[0].iocs[0]); }, 0x02, 27},
      {"IocsOfUnexpectedSubmodule",
       [](auto& q) {
         q.iocrs[0].apis[0].iocs.push_back({5, 1, 30});
       },
       0x02, 27},
      {"InputIocrIocsOfNoIoSubmodule",
       [](auto& q) {
         q.iocrs[0].apis[0].iocs.push_back({0, 1, 30});
       },
       0x02, 27},
      {"IocsBeyondDataLength", [](auto& q) { q.iocrs[0].apis[0].iocs[0].frame_offset = 40; }, 0x02,
       28},
      {"IocsOnAnotherSubmodulesData", [](auto& q) { q.iocrs[0].apis[0].iocs[0].frame_offset = 0; },
       0x02, 28},
      // pf_cmdev_check_apdu: block counts
      {"OutputIocrMissing", [](auto& q) { q.iocrs.pop_back(); }, 0x40, 2},
      {"AlarmCrMissing", [](auto& q) { q.alarm_cr_blocks = 0; }, 0x40, 3},
      {"AlarmCrTwice", [](auto& q) { q.alarm_cr_blocks = 2; }, 0x40, 3},
      // RT_CLASS_3 without an IRInfoBlock.
      {"RtClass3WithoutIrInfo",
       [](auto& q) {
         for (auto& c : q.iocrs) c.iocr_properties = 3;
         q.iocrs[0].frame_id = 0x0100;
       },
       0x40, 3},
      // pf_cmdev_check_alarm_cr
      {"AlarmCrTypeNot1", [](auto& q) { q.alarm_cr.alarm_cr_type = 2; }, 0x04, 4},
      {"AlarmCrLtNotProfinet", [](auto& q) { q.alarm_cr.lt = 0x0800; }, 0x04, 5},
      {"AlarmCrTimeoutFactor0", [](auto& q) { q.alarm_cr.rta_timeout_factor = 0; }, 0x04, 7},
      {"AlarmCrTimeoutFactor101", [](auto& q) { q.alarm_cr.rta_timeout_factor = 101; }, 0x04, 7},
      {"AlarmCrRetries2", [](auto& q) { q.alarm_cr.rta_retries = 2; }, 0x04, 8},
      {"AlarmCrRetries16", [](auto& q) { q.alarm_cr.rta_retries = 16; }, 0x04, 8},
      {"AlarmCrMaxData199", [](auto& q) { q.alarm_cr.max_alarm_data_length = 199; }, 0x04, 10},
      {"AlarmCrMaxData1433", [](auto& q) { q.alarm_cr.max_alarm_data_length = 1433; }, 0x04, 10},
      {"AlarmCrHighPriorityNot6", [](auto& q) { q.alarm_cr.tag_header_high = 0xA000; }, 0x04, 11},
      {"AlarmCrLowPriorityNot5", [](auto& q) { q.alarm_cr.tag_header_low = 0xC000; }, 0x04, 12},
      // pf_cmdev_check_ar_rpc
      {"ArRpcServerPortBelow0x400", [](auto& q) { q.ar_rpc = pn::ArRpcBlockReq{0x03FF}; }, 0x07, 4},
  };
  return r;
}

class DeviceConnectRefusal : public DeviceHarness, public ::testing::WithParamInterface<Refusal> {
 protected:
  void SetUp() override { make_device(); }
};

TEST_P(DeviceConnectRefusal, RefusedWithPnetStatus) {
  auto req = connect_request();
  GetParam().mutate(req);
  // The pure check first (no encode/decode in between) ...
  const auto direct = pn::check_connect(req, desc_);
  ASSERT_TRUE(direct.has_value());
  EXPECT_EQ(*direct, pn::connect_refusal(GetParam().code1, GetParam().code2));
  // ... then over the wire, when the codec can carry the mutation at all.
  const auto a = call(pn::rpc::kOpConnect, pn::encode_connect_request(req));
  ASSERT_TRUE(a.has_value());
  pn::ConnectRequest back;
  if (pn::decode_connect_request(pn::encode_connect_request(req), back))
    EXPECT_EQ(a->ndr.status, pn::connect_refusal(GetParam().code1, GetParam().code2));
  else
    EXPECT_FALSE(a->ndr.status.ok());
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Idle);
  EXPECT_TRUE(saw(pn::PnDeviceEvent::Kind::Refused));
  EXPECT_TRUE(frames_with_id(0xC001).empty());
}

INSTANTIATE_TEST_SUITE_P(PnetCmdevChecks, DeviceConnectRefusal, ::testing::ValuesIn(refusals()),
                         [](const auto& info) { return std::string(info.param.name); });

TEST_F(DeviceConnect, ValidRequestPassesEveryCheck) {
  EXPECT_FALSE(pn::check_connect(connect_request(), desc_).has_value());
}

TEST_F(DeviceConnect, FaultSwitchRefusesWithTheGivenStatus) {
  dev->faults().refuse_connect = pn::PnioStatus::from(0xDB810104);
  EXPECT_EQ(connect(connect_request()).value(), 0xDB810104u);
  dev->faults().refuse_connect.reset();
  EXPECT_TRUE(connect(connect_request()).ok());
}

// pf_cmrpc.c: an ARBlockReq whose BlockLength (2) leaves out its fields is
// a faulty AR block length (0x01 0x01); a block type we do not read is
// CMRPC "unknown blocks" (0x40 0x01).
TEST_F(DeviceConnect, UndecodableConnectIsRefusedWithPnetsReadingCodes) {
  const std::vector<std::uint8_t> short_ar{0x01, 0x01, 0x00, 0x02, 0x01, 0x00};
  auto a = call(pn::rpc::kOpConnect, short_ar);
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->ndr.status, pn::connect_refusal(0x01, 0x01));
  const std::vector<std::uint8_t> unknown{0x01, 0x55, 0x00, 0x02, 0x01, 0x00};
  a = call(pn::rpc::kOpConnect, unknown);
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->ndr.status, pn::connect_refusal(0x40, 0x01));
}

// IEC 61158-6-10 ModuleDiffBlock: an expected submodule ident we do not have
// in that subslot is accepted, listed as Wrong with our ident, and its data
// is not exchanged (IOPS bad).
TEST_F(DeviceConnect, DifferentSubmoduleIdentIsListedInModuleDiffAndGetsIopsBad) {
  auto req = connect_request();
  req.expected[1].modules[0].submodules[0].submodule_ident = 0x99;
  pn::ConnectResponse res;
  ASSERT_TRUE(connect(req, &res).ok());
  ASSERT_TRUE(res.module_diff.has_value());
  ASSERT_EQ(res.module_diff->apis.size(), 1u);
  ASSERT_EQ(res.module_diff->apis[0].modules.size(), 1u);
  const auto& m = res.module_diff->apis[0].modules[0];
  EXPECT_EQ(m.slot, 1);
  EXPECT_EQ(m.state, pn::module_state::kProperModule);
  ASSERT_EQ(m.submodules.size(), 1u);
  EXPECT_EQ(m.submodules[0].subslot, 1);
  EXPECT_EQ(m.submodules[0].submodule_ident, 0x11u);
  EXPECT_EQ(m.submodules[0].state, pn::submodule_state::kWrong);
  controller_frames();
  run(milliseconds(2));
  const auto frames = frames_with_id(0xC001);
  ASSERT_FALSE(frames.empty());
  pn::IocrLayout in;
  ASSERT_TRUE(pn::layout_from_iocr(req.iocrs[0], req.expected, in));
  pn::CyclicView v;
  ASSERT_TRUE(pn::decode_cyclic(frames.back(), in.c_sdu_length, v));
  const auto* io = in.find(0, 1, 1);
  ASSERT_NE(io, nullptr);
  EXPECT_EQ(pn::iops(v.c_sdu, *io), 0x00);
  const auto* dap = in.find(0, 0, 1);
  ASSERT_NE(dap, nullptr);
  EXPECT_EQ(pn::iops(v.c_sdu, *dap), 0x80);
}

TEST_F(DeviceConnect, DifferentModuleIdentIsWrongModule) {
  auto req = connect_request();
  req.expected[1].modules[0].module_ident = 0x77;
  pn::ConnectResponse res;
  ASSERT_TRUE(connect(req, &res).ok());
  ASSERT_TRUE(res.module_diff.has_value());
  const auto& m = res.module_diff->apis[0].modules[0];
  EXPECT_EQ(m.state, pn::module_state::kWrongModule);
  EXPECT_EQ(m.module_ident, 0x10u);
}

}  // namespace
}  // namespace pn_test

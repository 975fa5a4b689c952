// A whole PROFINET IO session built with the wire codec only: every PDU
// type in both directions, as the Ethernet frames a capture would show
// (RPC datagrams wrapped in IPv4/UDP). The round-trip tests decode these
// frames and the tshark test has Wireshark's dissectors decode them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plc/profinet/wire.hpp"

namespace plc::profinet::test {

inline constexpr Mac kCtrlMac{0x02, 0x00, 0x00, 0x00, 0x00, 0x01};
inline constexpr Mac kDevMac{0x02, 0x00, 0x00, 0x00, 0x00, 0x02};
inline constexpr std::uint32_t kCtrlIp = 0xC0A80A01;   // 192.168.10.1
inline constexpr std::uint32_t kDevIp = 0xC0A80A02;    // 192.168.10.2
inline constexpr std::uint16_t kCtrlRpcPort = 0xC001;  // the controller's client port
inline constexpr std::uint16_t kVendorId = 0x0493;
inline constexpr std::uint16_t kDeviceId = 0x0E01;
inline const std::string kStationName = "hiwin-e1";
inline const std::string kCtrlStationName = "softplc";
inline constexpr Uuid kArUuid{
    0x12345678, 0x9ABC, 0x4DEF, {0x81, 0x23, 0x45, 0x67, 0x89, 0xAB, 0xCD, 0xEF}};
inline constexpr Uuid kActivity{
    0xA1B2C3D4, 0x1111, 0x4222, {0x83, 0x33, 0x44, 0x44, 0x55, 0x55, 0x66, 0x66}};
inline constexpr std::uint16_t kInputFrameId = 0xC001;
inline constexpr std::uint16_t kOutputFrameId = 0xC002;
inline constexpr std::uint32_t kApiDrive = 0x3A00;

// DAP (slot 0: 0x0001, interface 0x8000, port 0x8001) and one telegram-111
// submodule in API 0x3A00 (24 bytes each way).
inline std::vector<ExpectedSubmoduleBlockReq> expected_submodules() {
  ExpectedSubmoduleBlockReq dap;
  dap.modules.push_back({0,
                         0,
                         0x00000001,
                         0,
                         {{0x0001, 0x00000001, 0, 0, 0, 1, 1},
                          {0x8000, 0x00000002, 0, 0, 0, 1, 1},
                          {0x8001, 0x00000003, 0, 0, 0, 1, 1}}});
  ExpectedSubmoduleBlockReq drive;
  drive.modules.push_back({kApiDrive, 1, 0x00000111, 0, {{0x0001, 0x00000111, 0, 24, 24, 1, 1}}});
  return {dap, drive};
}

inline ConnectRequest connect_request(const CyclicLayout& layout,
                                      const std::string& ctrl_name = kCtrlStationName) {
  ConnectRequest req;
  req.ar.ar_uuid = kArUuid;
  req.ar.session_key = 1;
  req.ar.cm_initiator_mac = kCtrlMac;
  req.ar.cm_initiator_object_uuid = pnio_object_uuid(1, 0x0001, 0x00FF);
  req.ar.station_name = ctrl_name;
  IocrBlockReq in;
  in.iocr_type = iocr::kTypeInput;
  in.iocr_reference = 1;
  in.frame_id = kInputFrameId;
  apply_layout(layout.input, in);
  IocrBlockReq out = in;
  out.iocr_type = iocr::kTypeOutput;
  out.iocr_reference = 2;
  out.frame_id = kOutputFrameId;
  apply_layout(layout.output, out);
  req.iocrs = {in, out};
  req.expected = expected_submodules();
  return req;
}

inline ConnectResponse connect_response(const std::string& device_name = kStationName) {
  ConnectResponse res;
  res.ar.ar_uuid = kArUuid;
  res.ar.session_key = 1;
  res.ar.cm_responder_mac = kDevMac;
  res.iocrs = {{iocr::kTypeInput, 1, kInputFrameId}, {iocr::kTypeOutput, 2, kOutputFrameId}};
  res.alarm_cr.local_alarm_reference = 0x0003;
  res.ar_server = ArServerBlock{device_name};
  return res;
}

struct Frame {
  std::string what;
  std::vector<std::uint8_t> bytes;
};

// One RPC exchange as two UDP/IPv4 frames (request to the server port).
inline void add_rpc(std::vector<Frame>& out, const std::string& what, bool ctrl_is_client,
                    std::uint16_t opnum, std::uint32_t seq,
                    const std::vector<std::uint8_t>& req_args,
                    const std::vector<std::uint8_t>& res_args, const PnioStatus& status = {}) {
  RpcHeader h;
  h.opnum = opnum;
  h.sequence_number = seq;
  h.activity = kActivity;
  h.activity.data1 += seq + (ctrl_is_client ? 0 : 0x1000);
  if (ctrl_is_client) {
    h.object = pnio_object_uuid(1, kDeviceId, kVendorId);
    h.interface = kPnioDeviceInterface;
  } else {
    h.object = pnio_object_uuid(1, 0x0001, 0x00FF);  // the CMInitiatorObjectUUID
    h.interface = kPnioControllerInterface;
  }
  const auto req = encode_rpc(h, encode_ndr_request(rpc::kMaxArgs, req_args));
  const auto res =
      encode_rpc(response_header_for(h), encode_ndr_response(status, rpc::kMaxArgs, res_args));
  const Mac& cm = ctrl_is_client ? kCtrlMac : kDevMac;
  const Mac& sm = ctrl_is_client ? kDevMac : kCtrlMac;
  const std::uint32_t cip = ctrl_is_client ? kCtrlIp : kDevIp;
  const std::uint32_t sip = ctrl_is_client ? kDevIp : kCtrlIp;
  const std::uint16_t cport = ctrl_is_client ? kCtrlRpcPort : 0xC002;
  out.push_back({what + " request", wrap_udp_ipv4(sm, cm, cip, cport, sip, kRpcUdpPort, req,
                                                  static_cast<std::uint16_t>(seq * 2))});
  out.push_back({what + " response", wrap_udp_ipv4(cm, sm, sip, kRpcUdpPort, cip, cport, res,
                                                   static_cast<std::uint16_t>(seq * 2 + 1))});
}

// The station names are parameters: names of odd length make DCP blocks
// and the ARBlockReq/ARServerBlock odd-sized (padding).
inline std::vector<Frame> whole_session(const std::string& device_name = kStationName,
                                        const std::string& ctrl_name = kCtrlStationName) {
  std::vector<Frame> f;
  DcpIdentity id;
  id.station_name = device_name;
  id.type_of_station = "HIWIN E1 servo";
  id.vendor_id = kVendorId;
  id.device_id = kDeviceId;
  id.ip = {kDevIp, 0xFFFFFF00, 0};
  id.device_instance = 0x0001;
  DcpIdentity unnamed = id;
  unnamed.station_name.clear();
  unnamed.ip = {};
  unnamed.ip_info = 0;

  f.push_back({"DCP identify all", encode_dcp_identify_request(kCtrlMac, 0x1001, std::nullopt, 1)});
  f.push_back({"DCP identify response (unnamed)",
               encode_dcp_identify_response(kCtrlMac, kDevMac, 0x1001, unnamed)});
  DcpSetRequest set;
  set.station_name = device_name;
  f.push_back({"DCP set name request", encode_dcp_set_request(kDevMac, kCtrlMac, 0x1002, set)});
  const DcpSetResult name_ok[] = {{dcp::kOptDevice, dcp::kSubDeviceNameOfStation, dcp::kErrorOk}};
  f.push_back(
      {"DCP set name response", encode_dcp_set_response(kCtrlMac, kDevMac, 0x1002, name_ok)});
  DcpSetRequest set_ip;
  set_ip.ip = DcpIpSuite{kDevIp, 0xFFFFFF00, 0};
  set_ip.permanent = false;
  f.push_back({"DCP set IP request", encode_dcp_set_request(kDevMac, kCtrlMac, 0x1003, set_ip)});
  const DcpSetResult ip_ok[] = {{dcp::kOptIp, dcp::kSubIpParameter, dcp::kErrorOk}};
  f.push_back({"DCP set IP response", encode_dcp_set_response(kCtrlMac, kDevMac, 0x1003, ip_ok)});
  f.push_back(
      {"DCP identify by name", encode_dcp_identify_request(kCtrlMac, 0x1004, device_name, 1)});
  f.push_back(
      {"DCP identify response", encode_dcp_identify_response(kCtrlMac, kDevMac, 0x1004, id)});
  const std::pair<std::uint8_t, std::uint8_t> get[] = {
      {dcp::kOptDevice, dcp::kSubDeviceNameOfStation}, {dcp::kOptIp, dcp::kSubIpParameter}};
  f.push_back({"DCP get request", encode_dcp_get_request(kDevMac, kCtrlMac, 0x1005, get)});
  f.push_back({"DCP get response", encode_dcp_get_response(kCtrlMac, kDevMac, 0x1005, id, get)});
  f.push_back({"DCP hello", encode_dcp_hello(kDevMac, 0x1006, id)});

  CyclicLayout layout;
  (void)compute_layout(expected_submodules(), layout);
  add_rpc(f, "Connect", true, rpc::kOpConnect, 0,
          encode_connect_request(connect_request(layout, ctrl_name)),
          encode_connect_response(connect_response(device_name)));

  // Start-up records: one MultipleWrite (two records, the first odd-sized
  // so padding goes between them), then a single write.
  const RecordWrite records[] = {{kApiDrive, 1, 1, 0x0100, {1, 2, 3}},
                                 {kApiDrive, 1, 1, 0x0101, {4, 5, 6, 7}}};
  WriteResponse mw;
  mw.header = {1,
               kArUuid,
               record::kApiMultipleWrite,
               record::kSlotMultipleWrite,
               record::kSubslotMultipleWrite,
               record::kIndexMultipleWrite,
               0,
               0,
               0,
               {}};
  std::uint32_t mw_len = 0;
  {
    const auto args = encode_write_request(1, kArUuid, records);
    ByteReader r(args);
    BlockView v;
    (void)read_block(r, v);
    mw_len = static_cast<std::uint32_t>(r.remaining());
  }
  mw.header.record_data_length = mw_len;
  for (const auto& r : records)
    mw.sub_results.push_back({1,
                              kArUuid,
                              r.api,
                              r.slot,
                              r.subslot,
                              r.index,
                              static_cast<std::uint32_t>(r.data.size()),
                              0,
                              0,
                              {}});
  add_rpc(f, "MultipleWrite", true, rpc::kOpWrite, 1, encode_write_request(1, kArUuid, records),
          encode_write_response(mw));
  const RecordWrite one[] = {{kApiDrive, 1, 1, 0x0102, {0x00, 0x2A}}};
  WriteResponse w1;
  w1.header = {2, kArUuid, kApiDrive, 1, 1, 0x0102, 2, 0, 0, {}};
  add_rpc(f, "Write", true, rpc::kOpWrite, 2, encode_write_request(2, kArUuid, one),
          encode_write_response(w1));
  ControlBlock prm{block::kPrmEndReq, kArUuid, 1, control::kPrmEnd, 0};
  add_rpc(f, "PrmEnd", true, rpc::kOpControl, 3, encode_control(prm),
          encode_control(control_response_for(prm)));
  ControlBlock ready{block::kApplicationReadyReq, kArUuid, 1, control::kApplicationReady, 0};
  add_rpc(f, "ApplicationReady", false, rpc::kOpControl, 0, encode_control(ready),
          encode_control(control_response_for(ready)));

  // Cyclic frames, both directions, each with good IOPS/IOCS.
  std::array<std::uint8_t, 1518> buf{};
  std::vector<std::uint8_t> c_sdu(layout.output.c_sdu_length, 0);
  for (const auto& o : layout.output.data) {
    std::vector<std::uint8_t> d(o.length, 0x11);
    put_io_data(c_sdu, o, d, iocr::kIoxsGood);
  }
  for (const auto& s : layout.output.iocs) c_sdu[s.offset] = iocr::kIoxsGood;
  CyclicHeader oh{kDevMac, kCtrlMac, std::nullopt, kOutputFrameId, 0x0020, data_status::kGood, 0};
  std::size_t n = encode_cyclic(buf, oh, c_sdu);
  f.push_back({"cyclic output", {buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n)}});
  std::vector<std::uint8_t> in_sdu(layout.input.c_sdu_length, 0);
  for (const auto& o : layout.input.data) {
    std::vector<std::uint8_t> d(o.length, 0x22);
    put_io_data(in_sdu, o, d, iocr::kIoxsGood);
  }
  for (const auto& s : layout.input.iocs) in_sdu[s.offset] = iocr::kIoxsGood;
  CyclicHeader ih{kCtrlMac,           kDevMac, kVlanTciPriority6, kInputFrameId, 0x0020,
                  data_status::kGood, 0};
  n = encode_cyclic(buf, ih, in_sdu);
  f.push_back(
      {"cyclic input (VLAN tagged)", {buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n)}});
  ih.vlan_tci.reset();
  ih.cycle_counter = 0x0040;
  n = encode_cyclic(buf, ih, in_sdu);
  f.push_back({"cyclic input", {buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n)}});

  // A diagnosis alarm, its ACK-RTA, the AlarmAck and that one's ACK-RTA.
  AlarmNotification an;
  an.high_priority = false;
  an.alarm_type = alarm_type::kDiagnosis;
  an.api = kApiDrive;
  an.slot = 1;
  an.subslot = 1;
  an.module_ident = 0x111;
  an.submodule_ident = 0x111;
  an.alarm_specifier =
      1 | alarm_specifier::kChannelDiagnosis | alarm_specifier::kSubmoduleDiagnosisState;
  an.user_structure_identifier = kUsiChannelDiagnosis;
  an.data = {0x80, 0x00, 0x08, 0x00, 0x00, 0x01};  // channel 0x8000, properties, error type 1
  RtaHeader dh{0x0001, 0x0003,          rta::kTypeData, rta::kAddFlagsWindow1 | rta::kAddFlagTack,
               0,      rta::kSeqInitial};
  f.push_back({"alarm notification", encode_alarm_notification(kCtrlMac, kDevMac, dh, an)});
  RtaHeader ack1{0x0003, 0x0001, rta::kTypeAck, rta::kAddFlagsWindow1, rta::kSeqInitial, 0};
  f.push_back({"alarm ACK-RTA (controller)", encode_rta_ack(kDevMac, kCtrlMac, false, ack1)});
  RtaHeader ch{0x0003, 0x0001, rta::kTypeData, rta::kAddFlagsWindow1 | rta::kAddFlagTack, 0, 0};
  f.push_back({"alarm ack", encode_alarm_ack(kDevMac, kCtrlMac, ch, ack_for(an))});
  RtaHeader ack2{0x0001, 0x0003, rta::kTypeAck, rta::kAddFlagsWindow1, 0, 0};
  f.push_back({"alarm ACK-RTA (device)", encode_rta_ack(kCtrlMac, kDevMac, false, ack2)});

  RecordRequestHeader rd{4, kArUuid, kApiDrive, 1, 1, 0x0100, 240};
  const std::uint8_t rec[] = {1, 2, 3};
  add_rpc(f, "Read", true, rpc::kOpRead, 4, encode_read_request(rd),
          encode_read_response({4, kArUuid, kApiDrive, 1, 1, 0x0100, 0, 0, 0, {}}, rec));
  ControlBlock rel{block::kReleaseReq, kArUuid, 1, control::kRelease, 0};
  add_rpc(f, "Release", true, rpc::kOpRelease, 5, encode_control(rel),
          encode_control(control_response_for(rel)));
  return f;
}

}  // namespace plc::profinet::test

// Every PDU of a session decodes back to what was encoded (both
// directions: what the controller encodes the device decodes and vice
// versa), and the decoders refuse bad input with a reason.
#include <gtest/gtest.h>

#include <array>

#include "test_wire_session.hpp"

namespace pn = plc::profinet;
namespace pt = plc::profinet::test;

namespace {

const pt::Frame& frame(const std::vector<pt::Frame>& s, const std::string& what) {
  for (const auto& f : s)
    if (f.what == what) return f;
  static pt::Frame none;
  ADD_FAILURE() << "no frame " << what;
  return none;
}

pn::DcpMessage dcp(const pt::Frame& f) {
  pn::PnFrameView v;
  EXPECT_TRUE(pn::decode_pn_frame(f.bytes, v));
  pn::DcpMessage m;
  const auto st = pn::decode_dcp(v.frame_id, v.pdu, m);
  EXPECT_TRUE(st) << f.what << ": " << st.reason;
  return m;
}

// The RPC datagram inside the pcap-only IPv4/UDP wrapping.
std::span<const std::uint8_t> udp_payload(const pt::Frame& f) {
  const std::size_t at = 14 + 20 + 8;
  const std::size_t len = (f.bytes[14 + 20 + 4] << 8 | f.bytes[14 + 20 + 5]) - 8u;
  return std::span<const std::uint8_t>(f.bytes).subspan(at, len);
}

struct Rpc {
  pn::RpcPdu pdu;
  std::span<const std::uint8_t> args;
  pn::PnioStatus status;
};
Rpc rpc_of(const pt::Frame& f, bool response) {
  Rpc r;
  const auto st = pn::decode_rpc(udp_payload(f), r.pdu);
  EXPECT_TRUE(st) << f.what << ": " << st.reason;
  if (response) {
    pn::NdrResponse n;
    EXPECT_TRUE(pn::decode_ndr_response(r.pdu.body, r.pdu.header.little_endian, n));
    r.args = n.args;
    r.status = n.status;
  } else {
    pn::NdrRequest n;
    EXPECT_TRUE(pn::decode_ndr_request(r.pdu.body, r.pdu.header.little_endian, n));
    r.args = n.args;
  }
  return r;
}

}  // namespace

// IEC 61158-6-10 §4.3 DCP: Identify (all / by name), Set, Get, Hello.
TEST(WireDcp, IdentifySetGetHelloRoundTrip) {
  const auto s = pt::whole_session();
  auto all = dcp(frame(s, "DCP identify all"));
  EXPECT_EQ(all.service_id, pn::dcp::kServiceIdentify);
  EXPECT_EQ(all.xid, 0x1001u);
  EXPECT_FALSE(pn::identify_filter(all).has_value());
  auto byname = dcp(frame(s, "DCP identify by name"));
  EXPECT_EQ(pn::identify_filter(byname), pt::kStationName);

  pn::DcpIdentity id;
  auto res = dcp(frame(s, "DCP identify response"));
  EXPECT_EQ(res.frame_id, pn::frame_id::kDcpIdentifyResponse);
  EXPECT_EQ(res.service_type, pn::dcp::kTypeResponseSuccess);
  ASSERT_TRUE(pn::identity_from(res, id));
  EXPECT_EQ(id.station_name, pt::kStationName);
  EXPECT_EQ(id.type_of_station, "HIWIN E1 servo");
  EXPECT_EQ(id.vendor_id, pt::kVendorId);
  EXPECT_EQ(id.device_id, pt::kDeviceId);
  EXPECT_EQ(id.ip.ip, pt::kDevIp);
  EXPECT_EQ(id.ip.netmask, 0xFFFFFF00u);
  EXPECT_EQ(id.device_instance, 0x0001);

  pn::DcpSetRequest set;
  ASSERT_TRUE(pn::set_request_from(dcp(frame(s, "DCP set name request")), set));
  EXPECT_EQ(set.station_name, pt::kStationName);
  EXPECT_TRUE(set.permanent);
  EXPECT_FALSE(set.ip.has_value());
  ASSERT_TRUE(pn::set_request_from(dcp(frame(s, "DCP set IP request")), set));
  ASSERT_TRUE(set.ip.has_value());
  EXPECT_EQ(set.ip->ip, pt::kDevIp);
  EXPECT_FALSE(set.permanent);
  std::vector<pn::DcpSetResult> results;
  ASSERT_TRUE(pn::set_results_from(dcp(frame(s, "DCP set IP response")), results));
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].option, pn::dcp::kOptIp);
  EXPECT_EQ(results[0].error, pn::dcp::kErrorOk);

  auto get = dcp(frame(s, "DCP get request"));
  ASSERT_EQ(get.blocks.size(), 2u);
  EXPECT_EQ(get.blocks[1].option, pn::dcp::kOptIp);
  ASSERT_TRUE(pn::identity_from(dcp(frame(s, "DCP get response")), id));
  EXPECT_EQ(id.station_name, pt::kStationName);

  auto hello = dcp(frame(s, "DCP hello"));
  EXPECT_EQ(hello.service_id, pn::dcp::kServiceHello);
  ASSERT_TRUE(pn::identity_from(hello, id));
  EXPECT_EQ(id.station_name, pt::kStationName);
}

// Frames are padded to the 60-byte Ethernet minimum; the identify request
// goes to the DCP multicast address 01:0E:CF:00:00:00.
TEST(WireDcp, IdentifyRequestIsPaddedMulticast) {
  const auto f = pn::encode_dcp_identify_request(pt::kCtrlMac, 7, std::nullopt);
  EXPECT_EQ(f.size(), pn::kMinFrameLength);
  pn::PnFrameView v;
  ASSERT_TRUE(pn::decode_pn_frame(f, v));
  EXPECT_EQ(v.dst, pn::kDcpIdentifyMulticast);
  EXPECT_EQ(v.frame_id, 0xFEFE);
}

// IEC 61158-6-10 DCP: a block of odd DCPBlockLength is followed by one
// padding octet, after the last block of a request too, and DCPDataLength
// counts it (as p-net's pf_dcp.c sends it and Wireshark reads it); an even
// block has none. Decoding takes the pad counted or not.
TEST(WireDcp, OddBlocksArePaddedAndThePadIsCountedInDcpDataLength) {
  for (const std::string name : {"rt-labs-dev", "hiwin-e1"}) {
    const bool odd = name.size() % 2 != 0;
    pn::PnFrameView v;
    const auto id = pn::encode_dcp_identify_request(pt::kCtrlMac, 7, name, 1);
    ASSERT_TRUE(pn::decode_pn_frame(id, v));
    EXPECT_EQ(v.pdu[8] << 8 | v.pdu[9], 4 + name.size() + (odd ? 1 : 0)) << name;
    EXPECT_EQ(v.pdu[12] << 8 | v.pdu[13], name.size());  // DCPBlockLength: no pad
    if (odd) {
      EXPECT_EQ(v.pdu[14 + name.size()], 0);
    }
    pn::DcpMessage m;
    ASSERT_TRUE(pn::decode_dcp(v.frame_id, v.pdu, m));
    EXPECT_EQ(pn::identify_filter(m), name);
    // The same request with the pad left out of DCPDataLength still reads.
    if (odd) {
      std::vector<std::uint8_t> uncounted(v.pdu.begin(), v.pdu.end());
      uncounted[9] = static_cast<std::uint8_t>(uncounted[9] - 1);
      ASSERT_TRUE(pn::decode_dcp(v.frame_id, uncounted, m));
      EXPECT_EQ(pn::identify_filter(m), name);
    }
    pn::DcpSetRequest set;
    set.station_name = name;
    const auto sf = pn::encode_dcp_set_request(pt::kDevMac, pt::kCtrlMac, 8, set);
    ASSERT_TRUE(pn::decode_pn_frame(sf, v));
    EXPECT_EQ(v.pdu[8] << 8 | v.pdu[9], 4 + 2 + name.size() + (odd ? 1 : 0)) << name;
    pn::DcpSetRequest back;
    ASSERT_TRUE(pn::decode_dcp(v.frame_id, v.pdu, m));
    ASSERT_TRUE(pn::set_request_from(m, back));
    EXPECT_EQ(back.station_name, name);
  }
}

// IEC 61158-6-10 NameOfStation rules.
TEST(WireDcp, StationNameRules) {
  EXPECT_TRUE(pn::valid_station_name("hiwin-e1"));
  EXPECT_TRUE(pn::valid_station_name("cell1.nord-profisafe"));
  EXPECT_FALSE(pn::valid_station_name(""));
  EXPECT_FALSE(pn::valid_station_name("Upper"));
  EXPECT_FALSE(pn::valid_station_name("-lead"));
  EXPECT_FALSE(pn::valid_station_name("trail-"));
  EXPECT_FALSE(pn::valid_station_name("a..b"));
  EXPECT_FALSE(pn::valid_station_name("192.168.0.1"));
  EXPECT_FALSE(pn::valid_station_name("port-001"));
  EXPECT_FALSE(pn::valid_station_name(std::string(64, 'a')));
}

// Truncated/overrunning DCP input is refused with a reason.
TEST(WireDcp, RefusesBadInput) {
  const auto f = pn::encode_dcp_identify_response(pt::kCtrlMac, pt::kDevMac, 1, {});
  pn::PnFrameView v;
  ASSERT_TRUE(pn::decode_pn_frame(f, v));
  pn::DcpMessage m;
  EXPECT_EQ(pn::decode_dcp(v.frame_id, v.pdu.first(5), m).error, pn::WireError::Truncated);
  std::vector<std::uint8_t> bad(v.pdu.begin(), v.pdu.end());
  bad[8] = 0xFF;  // DCPDataLength beyond the frame
  EXPECT_EQ(pn::decode_dcp(v.frame_id, bad, m).error, pn::WireError::BadLength);
  bad.assign(v.pdu.begin(), v.pdu.end());
  bad[0] = 9;  // ServiceID
  EXPECT_EQ(pn::decode_dcp(v.frame_id, bad, m).error, pn::WireError::BadHeader);
  EXPECT_EQ(pn::decode_dcp(0xC001, v.pdu, m).error, pn::WireError::BadFrameId);
  bad.assign(v.pdu.begin(), v.pdu.end());
  bad[13] = 0xF0;  // first block's length overruns DCPDataLength
  EXPECT_FALSE(pn::decode_dcp(v.frame_id, bad, m));
}

// DCE/RPC CL header (80 bytes, drep little-endian) + NDR, and the whole
// Connect request/response (IEC 61158-6-10 IODConnectReq/Res).
TEST(WireRpc, ConnectRoundTrip) {
  const auto s = pt::whole_session();
  const auto req = rpc_of(frame(s, "Connect request"), false);
  EXPECT_EQ(req.pdu.header.packet_type, pn::rpc::kRequest);
  EXPECT_EQ(req.pdu.header.opnum, pn::rpc::kOpConnect);
  EXPECT_EQ(req.pdu.header.interface, pn::kPnioDeviceInterface);
  EXPECT_EQ(req.pdu.header.object, pn::pnio_object_uuid(1, pt::kDeviceId, pt::kVendorId));
  EXPECT_EQ(req.pdu.header.activity, pt::kActivity);
  pn::ConnectRequest c;
  const auto st = pn::decode_connect_request(req.args, c);
  ASSERT_TRUE(st) << st.reason;
  EXPECT_EQ(c.ar.ar_uuid, pt::kArUuid);
  EXPECT_EQ(c.ar.station_name, pt::kCtrlStationName);
  EXPECT_EQ(c.ar.cm_initiator_mac, pt::kCtrlMac);
  ASSERT_EQ(c.iocrs.size(), 2u);
  EXPECT_EQ(c.iocrs[0].frame_id, pt::kInputFrameId);
  EXPECT_EQ(c.iocrs[1].iocr_type, pn::iocr::kTypeOutput);
  ASSERT_EQ(c.expected.size(), 2u);
  EXPECT_EQ(c.expected[0].modules[0].submodules.size(), 3u);
  EXPECT_EQ(c.expected[1].modules[0].api, pt::kApiDrive);
  EXPECT_EQ(c.expected[1].modules[0].submodules[0].input_length, 24);
  EXPECT_EQ(c.expected[1].modules[0].submodules[0].output_length, 24);
  // The re-encoding is byte-identical.
  EXPECT_EQ(pn::encode_connect_request(c),
            std::vector<std::uint8_t>(req.args.begin(), req.args.end()));

  const auto res = rpc_of(frame(s, "Connect response"), true);
  EXPECT_EQ(res.pdu.header.packet_type, pn::rpc::kResponse);
  EXPECT_EQ(res.pdu.header.activity, pt::kActivity);  // same activity as the request
  EXPECT_TRUE(res.status.ok());
  pn::ConnectResponse r;
  ASSERT_TRUE(pn::decode_connect_response(res.args, r));
  EXPECT_EQ(r.ar.cm_responder_mac, pt::kDevMac);
  ASSERT_EQ(r.iocrs.size(), 2u);
  EXPECT_EQ(r.iocrs[1].frame_id, pt::kOutputFrameId);
  EXPECT_EQ(r.alarm_cr.local_alarm_reference, 3);
  ASSERT_TRUE(r.ar_server.has_value());
  EXPECT_EQ(r.ar_server->station_name, pt::kStationName);
}

// The device rebuilds the controller's layout from the IOCRBlockReq
// offsets (what a device does with a Connect).
TEST(WireCyclic, DeviceLayoutFromConnectEqualsControllerLayout) {
  const auto exp = pt::expected_submodules();
  pn::CyclicLayout ctrl;
  ASSERT_TRUE(pn::compute_layout(exp, ctrl));
  const auto req = pt::connect_request(ctrl);
  pn::IocrLayout in, out;
  ASSERT_TRUE(pn::layout_from_iocr(req.iocrs[0], exp, in));
  ASSERT_TRUE(pn::layout_from_iocr(req.iocrs[1], exp, out));
  ASSERT_EQ(in.data.size(), ctrl.input.data.size());
  for (std::size_t i = 0; i < in.data.size(); ++i) {
    EXPECT_EQ(in.data[i].offset, ctrl.input.data[i].offset);
    EXPECT_EQ(in.data[i].length, ctrl.input.data[i].length);
  }
  EXPECT_EQ(out.iocs.size(), 4u);
  EXPECT_EQ(out.c_sdu_length, 40);
}

// IEC 61158-6-10 IO data object layout: NO_IO submodules (DAP, interface,
// port) get a lone IOPS in the input CR and an IOCS in the output CR;
// data objects first, then IOCS; C_SDU padded to 40 bytes.
TEST(WireCyclic, LayoutPerIec61158_6_10) {
  pn::CyclicLayout l;
  ASSERT_TRUE(pn::compute_layout(pt::expected_submodules(), l));
  ASSERT_EQ(l.input.data.size(), 4u);
  EXPECT_EQ(l.input.data[0].offset, 0);  // DAP 0x0001: IOPS only
  EXPECT_EQ(l.input.data[0].length, 0);
  EXPECT_EQ(l.input.data[1].offset, 1);  // 0x8000
  EXPECT_EQ(l.input.data[2].offset, 2);  // 0x8001
  EXPECT_EQ(l.input.data[3].offset, 3);  // drive: 24 bytes + IOPS at 27
  EXPECT_EQ(l.input.data[3].iops_offset(), 27);
  ASSERT_EQ(l.input.iocs.size(), 1u);  // the drive's output
  EXPECT_EQ(l.input.iocs[0].offset, 28);
  EXPECT_EQ(l.input.c_sdu_length, 40);
  ASSERT_EQ(l.output.data.size(), 1u);
  EXPECT_EQ(l.output.data[0].offset, 0);
  ASSERT_EQ(l.output.iocs.size(), 4u);
  EXPECT_EQ(l.output.iocs[0].offset, 25);
  EXPECT_EQ(l.output.iocs[3].offset, 28);
}

TEST(WireCyclic, LargeLayoutIsNotPaddedAndTooLargeIsRefused) {
  std::vector<pn::ExpectedSubmoduleBlockReq> exp(1);
  exp[0].modules.push_back({0, 1, 1, 0, {{1, 1, 0, 100, 0, 1, 1}}});
  pn::CyclicLayout l;
  ASSERT_TRUE(pn::compute_layout(exp, l));
  EXPECT_EQ(l.input.c_sdu_length, 101);
  exp[0].modules[0].submodules[0].input_length = 1440;
  EXPECT_EQ(pn::compute_layout(exp, l).error, pn::WireError::BadLength);
}

// An IOCR whose offsets overlap another submodule's bytes or run past
// DataLength, or that lists an entry twice, is refused; one that leaves a
// submodule out is taken as p-net takes it (that submodule's bytes do not
// travel), and so is a submodule's IOCS on its own data (p-net compares a
// submodule with the others only).
TEST(WireCyclic, LayoutFromIocrRefusesOverlapAndTakesMissingEntries) {
  const auto exp = pt::expected_submodules();
  pn::CyclicLayout ctrl;
  ASSERT_TRUE(pn::compute_layout(exp, ctrl));
  auto req = pt::connect_request(ctrl);
  pn::IocrLayout l;
  auto overlap = req.iocrs[0];
  overlap.apis[0].data_objects[1].frame_offset = 0;
  EXPECT_EQ(pn::layout_from_iocr(overlap, exp, l).error, pn::WireError::BadLength);
  auto twice = req.iocrs[0];
  twice.apis[0].data_objects.push_back(twice.apis[0].data_objects.back());
  EXPECT_EQ(pn::layout_from_iocr(twice, exp, l).error, pn::WireError::BadValue);
  auto missing = req.iocrs[0];
  missing.apis[0].data_objects.pop_back();
  ASSERT_TRUE(pn::layout_from_iocr(missing, exp, l));
  EXPECT_EQ(l.data.size(), ctrl.input.data.size() - 1);
  auto no_iocs = req.iocrs[1];
  for (auto& a : no_iocs.apis) a.iocs.clear();
  ASSERT_TRUE(pn::layout_from_iocr(no_iocs, exp, l));
  EXPECT_TRUE(l.iocs.empty());
  auto own = req.iocrs[0];
  for (auto& a : own.apis)
    for (auto& s : a.iocs) s.frame_offset = 3;  // the drive's IOCS on the drive's data
  ASSERT_TRUE(pn::layout_from_iocr(own, exp, l));
  auto past = req.iocrs[1];
  ASSERT_EQ(past.apis[0].api, pt::kApiDrive);
  ASSERT_EQ(past.apis[0].data_objects.size(), 1u);
  past.apis[0].data_objects[0].frame_offset = 20;  // 20 + 24 + 1 > 40
  EXPECT_EQ(pn::layout_from_iocr(past, exp, l).error, pn::WireError::BadLength);
}

// RT_CLASS_1 frame: C_SDU, CycleCounter, DataStatus, TransferStatus;
// tagged and untagged; no allocation (caller buffers).
TEST(WireCyclic, FrameRoundTripTaggedAndUntagged) {
  std::array<std::uint8_t, 64> c_sdu{};
  for (std::size_t i = 0; i < c_sdu.size(); ++i) c_sdu[i] = static_cast<std::uint8_t>(i);
  for (bool tagged : {false, true}) {
    std::array<std::uint8_t, pn::kMaxFrameLength> buf{};
    pn::CyclicHeader h{pt::kCtrlMac, pt::kDevMac, std::nullopt, 0xC123, 0xFFF0, 0x35, 0};
    if (tagged) h.vlan_tci = pn::kVlanTciPriority6;
    const std::size_t n = pn::encode_cyclic(buf, h, c_sdu);
    EXPECT_EQ(n, pn::cyclic_frame_length(64, tagged));
    pn::CyclicView v;
    ASSERT_TRUE(pn::decode_cyclic(std::span(buf).first(n), 64, v));
    EXPECT_EQ(v.header.frame_id, 0xC123);
    EXPECT_EQ(v.header.cycle_counter, 0xFFF0);
    EXPECT_EQ(v.header.data_status, 0x35);
    EXPECT_EQ(v.header.src, pt::kDevMac);
    EXPECT_EQ(v.header.vlan_tci.has_value(), tagged);
    EXPECT_TRUE(std::equal(v.c_sdu.begin(), v.c_sdu.end(), c_sdu.begin()));
    // Short C_SDU: padded to 40 with zeros.
    const std::size_t m = pn::encode_cyclic(buf, h, std::span(c_sdu).first(3));
    EXPECT_EQ(m, pn::cyclic_frame_length(40, tagged));
    ASSERT_TRUE(pn::decode_cyclic(std::span(buf).first(m), 40, v));
    EXPECT_EQ(v.c_sdu[2], 2);
    EXPECT_EQ(v.c_sdu[3], 0);
    // Truncated frame and wrong FrameID refused.
    EXPECT_EQ(pn::decode_cyclic(std::span(buf).first(m - 1), 40, v).error,
              pn::WireError::Truncated);
  }
  std::array<std::uint8_t, 20> small{};
  EXPECT_EQ(pn::encode_cyclic(small, {}, c_sdu), 0u);
  const auto dcp = pn::encode_dcp_identify_request(pt::kCtrlMac, 1, std::nullopt);
  pn::CyclicView v;
  EXPECT_EQ(pn::decode_cyclic(dcp, 40, v).error, pn::WireError::BadFrameId);
}

// A frame built once per AR and sent again and again: put_cyclic_status()
// rewrites the APDU status (CycleCounter, DataStatus, TransferStatus after
// the C_SDU, IEC 61158-6-10 §4.7) and nothing else: the frame is byte for
// byte the one finish_cyclic() builds with that status.
TEST(WireCyclic, StatusRewrittenInPlaceEqualsAFreshlyFinishedFrame) {
  for (bool tagged : {false, true}) {
    std::array<std::uint8_t, 128> once{}, fresh{};
    pn::CyclicHeader h{pt::kDevMac, pt::kCtrlMac, std::nullopt, 0x8001, 0, 0x35, 0};
    if (tagged) h.vlan_tci = pn::kVlanTciPriority6;
    for (std::size_t i = 0; i < 40; ++i)
      pn::cyclic_c_sdu(once, 40, tagged)[i] = static_cast<std::uint8_t>(0xA0 + i);
    fresh = once;
    const std::size_t n = pn::finish_cyclic(once, h, 40);
    ASSERT_EQ(n, pn::cyclic_frame_length(40, tagged));
    EXPECT_EQ(pn::put_cyclic_status(once, 40, tagged, 0x1234, 0x15, 0x01), n);
    h.cycle_counter = 0x1234;
    h.data_status = 0x15;
    h.transfer_status = 0x01;
    ASSERT_EQ(pn::finish_cyclic(fresh, h, 40), n);
    EXPECT_EQ(once, fresh);
    EXPECT_EQ(once[n - 4], 0x12);
    EXPECT_EQ(once[n - 3], 0x34);
    EXPECT_EQ(once[n - 2], 0x15);
    EXPECT_EQ(once[n - 1], 0x01);
    EXPECT_EQ(pn::put_cyclic_status(std::span(once).first(n - 1), 40, tagged, 1, 0x35, 0), 0u);
  }
}

// p-net's cycle counter rule: advanced by 1..61440 (mod 2^16).
TEST(WireCyclic, CycleCounterAdvance) {
  EXPECT_TRUE(pn::cycle_counter_advanced(10, 11));
  EXPECT_TRUE(pn::cycle_counter_advanced(0xFFFF, 31));
  EXPECT_FALSE(pn::cycle_counter_advanced(10, 10));
  EXPECT_FALSE(pn::cycle_counter_advanced(10, 9));
  EXPECT_TRUE(pn::cycle_counter_advanced(0, 61440));
  EXPECT_FALSE(pn::cycle_counter_advanced(0, 61441));
}

// IODWriteReq with MultipleWrite 0xE040: padding between records, not after
// the last (fieldbus-masters.md §1 step 3).
TEST(WireRecord, MultipleWriteRoundTripAndPadding) {
  const auto s = pt::whole_session();
  const auto req = rpc_of(frame(s, "MultipleWrite request"), false);
  EXPECT_EQ(req.pdu.header.opnum, pn::rpc::kOpWrite);
  pn::WriteRequest w;
  const auto st = pn::decode_write_request(req.args, w);
  ASSERT_TRUE(st) << st.reason;
  EXPECT_TRUE(w.multiple());
  EXPECT_EQ(w.header.api, pn::record::kApiMultipleWrite);
  ASSERT_EQ(w.sub_headers.size(), 2u);
  EXPECT_EQ(w.sub_headers[0].index, 0x0100);
  EXPECT_EQ(w.sub_data[0].size(), 3u);
  EXPECT_EQ(w.sub_data[1][3], 7);
  // 64 + 3 + 1 pad + 64 + 4 = 136 bytes, no pad after the last record.
  EXPECT_EQ(w.header.record_data_length, 136u);
  EXPECT_EQ(req.args.size(), 64u + 136u);

  pn::WriteResponse wr;
  ASSERT_TRUE(pn::decode_write_response(rpc_of(frame(s, "MultipleWrite response"), true).args, wr));
  ASSERT_EQ(wr.sub_results.size(), 2u);
  EXPECT_EQ(wr.sub_results[1].index, 0x0101);
  EXPECT_TRUE(wr.sub_results[1].status.ok());

  const auto one = rpc_of(frame(s, "Write request"), false);
  ASSERT_TRUE(pn::decode_write_request(one.args, w));
  EXPECT_FALSE(w.multiple());
  EXPECT_EQ(w.header.index, 0x0102);
  ASSERT_EQ(w.data.size(), 2u);
  EXPECT_EQ(w.data[1], 0x2A);
}

TEST(WireRecord, ReadRoundTrip) {
  const auto s = pt::whole_session();
  pn::RecordRequestHeader h;
  ASSERT_TRUE(pn::decode_read_request(rpc_of(frame(s, "Read request"), false).args, h));
  EXPECT_EQ(h.index, 0x0100);
  EXPECT_EQ(h.record_data_length, 240u);
  EXPECT_EQ(h.ar_uuid, pt::kArUuid);
  pn::RecordResponseHeader r;
  std::span<const std::uint8_t> data;
  ASSERT_TRUE(pn::decode_read_response(rpc_of(frame(s, "Read response"), true).args, r, data));
  ASSERT_EQ(data.size(), 3u);
  EXPECT_EQ(data[2], 3);
}

TEST(WireRecord, RefusesBadLengths) {
  const pn::RecordWrite one[] = {{0, 1, 1, 0x10, {1, 2, 3, 4}}};
  auto args = pn::encode_write_request(1, pt::kArUuid, one);
  pn::WriteRequest w;
  args.pop_back();  // RecordDataLength now says one byte more than follows
  EXPECT_EQ(pn::decode_write_request(args, w).error, pn::WireError::BadLength);
  args[1] = 0x99;  // block type
  EXPECT_EQ(pn::decode_write_request(args, w).error, pn::WireError::BadBlockType);
  auto ver = pn::encode_write_request(1, pt::kArUuid, one);
  ver[5] = 1;  // version 1.1
  EXPECT_EQ(pn::decode_write_request(ver, w).error, pn::WireError::BadBlockVersion);
  EXPECT_EQ(pn::decode_write_request(std::span(ver).first(3), w).error, pn::WireError::Truncated);
}

// IODControlReq/Res (PrmEnd 0x0110/0x8110), IOXControlReq/Res
// (ApplicationReady 0x0112/0x8112, answered with DONE to the controller's
// CMInitiatorObjectUUID), IODReleaseReq/Res (0x0114/0x8114).
TEST(WireControl, PrmEndApplicationReadyReleaseRoundTrip) {
  const auto s = pt::whole_session();
  struct Case {
    const char* what;
    std::uint16_t req_type, command;
  };
  for (const Case c :
       {Case{"PrmEnd", pn::block::kPrmEndReq, pn::control::kPrmEnd},
        Case{"ApplicationReady", pn::block::kApplicationReadyReq, pn::control::kApplicationReady},
        Case{"Release", pn::block::kReleaseReq, pn::control::kRelease}}) {
    pn::ControlBlock req, res;
    const auto rq = rpc_of(frame(s, std::string(c.what) + " request"), false);
    ASSERT_TRUE(pn::decode_control(rq.args, req)) << c.what;
    EXPECT_EQ(req.block_type, c.req_type);
    EXPECT_EQ(req.command, c.command);
    EXPECT_EQ(req.ar_uuid, pt::kArUuid);
    EXPECT_EQ(req.session_key, 1);
    ASSERT_TRUE(
        pn::decode_control(rpc_of(frame(s, std::string(c.what) + " response"), true).args, res));
    EXPECT_EQ(res.block_type, c.req_type | 0x8000);
    EXPECT_EQ(res.command, pn::control::kDone);
  }
  const auto ar = rpc_of(frame(s, "ApplicationReady request"), false);
  EXPECT_EQ(ar.pdu.header.interface, pn::kPnioControllerInterface);
  EXPECT_EQ(ar.pdu.header.object, pn::pnio_object_uuid(1, 0x0001, 0x00FF));
  pn::ControlBlock cb;
  EXPECT_EQ(pn::decode_control(rpc_of(frame(s, "Read request"), false).args, cb).error,
            pn::WireError::BadBlockType);
}

TEST(WireRpc, RefusesBadHeaders) {
  const auto s = pt::whole_session();
  const auto d = udp_payload(frame(s, "PrmEnd request"));
  std::vector<std::uint8_t> b(d.begin(), d.end());
  pn::RpcPdu p;
  ASSERT_TRUE(pn::decode_rpc(b, p));
  EXPECT_EQ(pn::decode_rpc(std::span(b).first(79), p).error, pn::WireError::Truncated);
  auto v = b;
  v[0] = 5;
  EXPECT_EQ(pn::decode_rpc(v, p).error, pn::WireError::BadHeader);
  v = b;
  v[2] |= pn::rpc::kFlagFragment;
  EXPECT_EQ(pn::decode_rpc(v, p).error, pn::WireError::BadHeader);
  v = b;
  v[74] = 0xFF;  // body length beyond the datagram
  EXPECT_EQ(pn::decode_rpc(v, p).error, pn::WireError::BadLength);
  // NDR: ArgsLength above ArgsMaximum, ActualCount disagreeing.
  ASSERT_TRUE(pn::decode_rpc(b, p));
  std::vector<std::uint8_t> body(p.body.begin(), p.body.end());
  pn::NdrRequest n;
  auto bad = body;
  bad[16] = static_cast<std::uint8_t>(bad[16] + 1);
  EXPECT_EQ(pn::decode_ndr_request(bad, true, n).error, pn::WireError::BadLength);
  bad = body;
  bad[0] = 1;
  bad[1] = 0;  // ArgsMaximum 1
  EXPECT_EQ(pn::decode_ndr_request(bad, true, n).error, pn::WireError::BadLength);
}

// Big-endian drep (drep[0] = 0x00) is decoded too.
TEST(WireRpc, BigEndianDrepRoundTrip) {
  pn::RpcHeader h;
  h.little_endian = false;
  h.object = pn::pnio_object_uuid(1, 2, 3);
  h.interface = pn::kPnioDeviceInterface;
  h.activity = pt::kActivity;
  h.sequence_number = 0x01020304;
  h.opnum = pn::rpc::kOpRead;
  const std::uint8_t args[] = {9, 8, 7};
  const auto d = pn::encode_rpc(h, pn::encode_ndr_request(100, args, false));
  EXPECT_EQ(d[4], 0x00);
  EXPECT_EQ(d[8], 0xDE);  // object UUID data1 big-endian
  pn::RpcPdu p;
  ASSERT_TRUE(pn::decode_rpc(d, p));
  EXPECT_FALSE(p.header.little_endian);
  EXPECT_EQ(p.header.object, h.object);
  EXPECT_EQ(p.header.sequence_number, 0x01020304u);
  pn::NdrRequest n;
  ASSERT_TRUE(pn::decode_ndr_request(p.body, false, n));
  EXPECT_EQ(n.args_maximum, 100u);
  ASSERT_EQ(n.args.size(), 3u);
}

// The UUID text form and the drep rule: little-endian in the RPC header,
// big-endian in blocks (fieldbus-masters.md §1 step 2).
TEST(WireRpc, UuidByteOrders) {
  pn::Uuid u;
  ASSERT_TRUE(pn::Uuid::parse("dea00001-6c97-11d1-8271-00a02442df7d", u));
  EXPECT_EQ(u, pn::kPnioDeviceInterface);
  EXPECT_EQ(u.to_string(), "dea00001-6c97-11d1-8271-00a02442df7d");
  std::vector<std::uint8_t> be, le;
  pn::ByteBuilder bb(be), lb(le);
  pn::put_uuid(bb, u);
  pn::put_uuid(lb, u, true);
  EXPECT_EQ(be[0], 0xDE);
  EXPECT_EQ(le[0], 0x01);
  EXPECT_EQ(le[3], 0xDE);
  EXPECT_EQ(le[4], 0x97);
  EXPECT_EQ(le[8], 0x82);  // data4 is a byte array in both
  EXPECT_FALSE(pn::Uuid::parse("dea00001-6c97-11d1-8271-00a02442df7", u));
  EXPECT_FALSE(pn::Uuid::parse("dea00001x6c97-11d1-8271-00a02442df7d", u));
}

// RTA: DATA with AlarmNotification / AlarmAck, ACK-RTA, sequence numbers.
TEST(WireAlarm, NotificationAckRoundTrip) {
  const auto s = pt::whole_session();
  auto rta = [](const pt::Frame& f) {
    pn::PnFrameView v;
    EXPECT_TRUE(pn::decode_pn_frame(f.bytes, v));
    pn::RtaPdu p;
    const auto st = pn::decode_rta(v.frame_id, v.pdu, p);
    EXPECT_TRUE(st) << f.what << ": " << st.reason;
    return p;
  };
  const auto n = rta(frame(s, "alarm notification"));
  ASSERT_TRUE(n.notification.has_value());
  EXPECT_EQ(n.header.pdu_type, pn::rta::kTypeData);
  EXPECT_EQ(n.header.send_seq, 0);
  EXPECT_EQ(n.header.ack_seq, pn::rta::kSeqInitial);
  EXPECT_EQ(n.header.src_endpoint, 3);
  EXPECT_EQ(n.notification->alarm_type, pn::alarm_type::kDiagnosis);
  EXPECT_EQ(n.notification->api, pt::kApiDrive);
  EXPECT_EQ(n.notification->user_structure_identifier, pn::kUsiChannelDiagnosis);
  EXPECT_EQ(n.notification->data.size(), 6u);
  const auto ack = rta(frame(s, "alarm ACK-RTA (controller)"));
  EXPECT_EQ(ack.header.pdu_type, pn::rta::kTypeAck);
  EXPECT_EQ(ack.header.ack_seq, 0);
  const auto aa = rta(frame(s, "alarm ack"));
  ASSERT_TRUE(aa.ack.has_value());
  EXPECT_EQ(aa.ack->alarm_specifier, n.notification->alarm_specifier);
  EXPECT_TRUE(aa.ack->status.ok());
  EXPECT_EQ(pn::rta::next_seq(0x7FFF), 0);
  EXPECT_EQ(pn::rta::next_seq(pn::rta::kSeqInitial), 0);
}

TEST(WireAlarm, RefusesBadRta) {
  const auto s = pt::whole_session();
  pn::PnFrameView v;
  ASSERT_TRUE(pn::decode_pn_frame(frame(s, "alarm notification").bytes, v));
  std::vector<std::uint8_t> b(v.pdu.begin(), v.pdu.end());
  pn::RtaPdu p;
  EXPECT_EQ(pn::decode_rta(v.frame_id, std::span(b).first(11), p).error, pn::WireError::Truncated);
  auto bad = b;
  bad[4] = 0x21;  // version 2
  EXPECT_EQ(pn::decode_rta(v.frame_id, bad, p).error, pn::WireError::BadHeader);
  bad = b;
  bad[10] = 0x7F;  // VarPartLen beyond the frame
  EXPECT_EQ(pn::decode_rta(v.frame_id, bad, p).error, pn::WireError::BadLength);
  // A low-priority notification on the high-priority FrameID.
  EXPECT_EQ(pn::decode_rta(pn::frame_id::kAlarmHigh, b, p).error, pn::WireError::BadBlockType);
}

// Ethernet header: with and without a VLAN tag; other EtherTypes refused.
TEST(WireEthernet, TaggedAndUntaggedAndOtherEtherTypes) {
  const std::uint8_t pdu[] = {1, 2, 3};
  const auto t = pn::build_pn_frame(pt::kDevMac, pt::kCtrlMac, 0xFE01, pdu, 0xC000);
  pn::PnFrameView v;
  ASSERT_TRUE(pn::decode_pn_frame(t, v));
  EXPECT_EQ(v.vlan_tci, 0xC000);
  EXPECT_EQ(v.frame_id, 0xFE01);
  EXPECT_EQ(v.pdu[0], 1);
  const auto s = pt::whole_session();
  EXPECT_EQ(pn::decode_pn_frame(frame(s, "PrmEnd request").bytes, v).error,
            pn::WireError::BadEtherType);
  EXPECT_EQ(pn::decode_pn_frame(std::span(t).first(17), v).error, pn::WireError::Truncated);
}

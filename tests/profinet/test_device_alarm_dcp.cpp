// PnDevice alarms over RTA (IEC 61158-6-10 §4.9; fieldbus-masters.md §1
// item 7) and DCP (item 1: Identify with the response delay, Get/Set
// NameOfStation and IP).
#include "test_device_harness.hpp"

namespace pn_test {
namespace {

class DeviceAlarm : public DeviceHarness {
 protected:
  void SetUp() override {
    make_device();
    bring_up();
    controller_frames();
  }
  // The alarm DATA-RTA frames the device sent since the last call.
  std::vector<pn::RtaPdu> alarms(std::uint16_t frame_id = pn::frame_id::kAlarmLow) {
    std::vector<pn::RtaPdu> out;
    for (const auto& f : frames_with_id(frame_id)) {
      pn::PnFrameView v;
      pn::RtaPdu p;
      EXPECT_TRUE(pn::decode_pn_frame(f, v));
      EXPECT_TRUE(pn::decode_rta(v.frame_id, v.pdu, p));
      out.push_back(p);
    }
    return out;
  }
  // Virtual time with the controller's output frames going on (1 ms).
  void run_alive(nanoseconds d) {
    for (nanoseconds end = now + d; now < end;) {
      const std::array<std::uint8_t, 4> out{1, 2, 3, 4};
      send_output(out);
      run(milliseconds(1));
    }
  }
  pn::RtaHeader from_controller(std::uint8_t type, std::uint16_t send, std::uint16_t ack) {
    pn::RtaHeader h;
    h.dst_endpoint = 1;  // the device's LocalAlarmReference (AlarmCRBlockRes)
    h.src_endpoint = 1;  // ours in the AlarmCRBlockReq
    h.pdu_type = type;
    h.send_seq = send;
    h.ack_seq = ack;
    return h;
  }
};

TEST_F(DeviceAlarm, DiagnosisAlarmIsRepeatedUntilAckRtaThenCompletedByAlarmAck) {
  ASSERT_TRUE(dev->raise_alarm(pn::AlarmKind::Diagnosis));
  EXPECT_FALSE(dev->raise_alarm(pn::AlarmKind::Diagnosis));  // one at a time per priority
  run(milliseconds(1));
  auto sent = alarms();
  ASSERT_EQ(sent.size(), 1u);
  const pn::RtaPdu first = sent[0];
  EXPECT_EQ(first.header.pdu_type & 0x0F, pn::rta::kTypeData);
  EXPECT_EQ(first.header.send_seq, 0);      // first DATA after 0xFFFF
  EXPECT_EQ(first.header.ack_seq, 0xFFFF);  // nothing received yet
  ASSERT_TRUE(first.notification.has_value());
  EXPECT_EQ(first.notification->alarm_type, pn::alarm_type::kDiagnosis);
  EXPECT_EQ(first.notification->slot, 1);
  EXPECT_EQ(first.notification->subslot, 1);
  EXPECT_EQ(first.notification->module_ident, 0x10u);
  EXPECT_EQ(first.notification->submodule_ident, 0x11u);
  // No ACK-RTA: repeated after RTATimeoutFactor (1) x 100 ms.
  run_alive(milliseconds(98));
  EXPECT_TRUE(alarms().empty());
  run_alive(milliseconds(2));
  sent = alarms();
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].header.send_seq, 0);  // the same PDU again
  // ACK-RTA: no more repeats.
  ctl_eth->send(
      pn::encode_rta_ack(kDevMac, kCtlMac, false, from_controller(pn::rta::kTypeAck, 0xFFFF, 0)));
  run_alive(milliseconds(500));
  EXPECT_TRUE(alarms().empty());
  EXPECT_EQ(dev->counters().alarm_repeats, 1u);
  // The AlarmAck (DATA-RTA) is acknowledged with an ACK-RTA and ends it.
  ctl_eth->send(pn::encode_alarm_ack(kDevMac, kCtlMac, from_controller(pn::rta::kTypeData, 0, 0),
                                     pn::ack_for(*first.notification)));
  run(milliseconds(1));
  const auto acks = alarms();
  ASSERT_EQ(acks.size(), 1u);
  EXPECT_EQ(acks[0].header.pdu_type & 0x0F, pn::rta::kTypeAck);
  EXPECT_EQ(acks[0].header.ack_seq, 0);
  EXPECT_TRUE(saw(pn::PnDeviceEvent::Kind::AlarmAcked));
  // The next alarm carries the next sequence numbers.
  ASSERT_TRUE(dev->raise_alarm(pn::AlarmKind::Diagnosis));
  run(milliseconds(1));
  sent = alarms();
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].header.send_seq, 1);
  EXPECT_EQ(sent[0].header.ack_seq, 0);
  EXPECT_NE(sent[0].notification->alarm_specifier & pn::alarm_specifier::kSequenceMask,
            first.notification->alarm_specifier & pn::alarm_specifier::kSequenceMask);
}

TEST_F(DeviceAlarm, ProcessAlarmGoesHighPriority) {
  ASSERT_TRUE(dev->raise_alarm(pn::AlarmKind::Process));
  run(milliseconds(1));
  const auto sent = alarms(pn::frame_id::kAlarmHigh);
  ASSERT_EQ(sent.size(), 1u);
  ASSERT_TRUE(sent[0].notification.has_value());
  EXPECT_TRUE(sent[0].notification->high_priority);
  EXPECT_EQ(sent[0].notification->alarm_type, pn::alarm_type::kProcess);
}

// RTARetries (3) repeats without an ACK-RTA: the AR is aborted.
TEST_F(DeviceAlarm, UnacknowledgedAlarmAbortsTheArAfterRtaRetries) {
  ASSERT_TRUE(dev->raise_alarm(pn::AlarmKind::Diagnosis));
  for (int i = 0; i < 10 && dev->state() != pn::PnDeviceState::Idle; ++i)
    run_alive(milliseconds(100));
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Idle);
  EXPECT_EQ(dev->counters().alarm_repeats, 3u);
  EXPECT_EQ(events.back().end, pn::ArEnd::AlarmTimeout);
}

TEST_F(DeviceAlarm, NoAlarmWithoutAnAr) {
  pn::ControlBlock c;
  c.block_type = pn::block::kReleaseReq;
  c.ar_uuid = kArUuid;
  c.session_key = 7;
  c.command = pn::control::kRelease;
  ASSERT_TRUE(call(pn::rpc::kOpRelease, pn::encode_control(c)).has_value());
  EXPECT_FALSE(dev->raise_alarm(pn::AlarmKind::Diagnosis));
}

class DeviceDcp : public DeviceHarness {
 protected:
  void SetUp() override { make_device(); }
  std::vector<pn::DcpMessage> dcp_answers() {
    std::vector<pn::DcpMessage> out;
    for (const auto& f : controller_frames()) {
      pn::PnFrameView v;
      pn::DcpMessage m;
      if (pn::decode_pn_frame(f, v) && pn::is_dcp(v.frame_id) &&
          pn::decode_dcp(v.frame_id, v.pdu, m))
        out.push_back(m);
    }
    return out;
  }
};

TEST(DcpResponseDelay, MacModFactorTimesTenMs) {
  const pn::Mac mac{2, 0, 0, 0, 0x12, 0x34};  // 0x1234 = 4660
  EXPECT_EQ(pn::dcp_response_delay(mac, 0), nanoseconds(0));
  EXPECT_EQ(pn::dcp_response_delay(mac, 1), nanoseconds(0));
  EXPECT_EQ(pn::dcp_response_delay(mac, 100), milliseconds(600));   // 4660 mod 100 = 60
  EXPECT_EQ(pn::dcp_response_delay(mac, 400), milliseconds(2600));  // 4660 mod 400 = 260
}

TEST_F(DeviceDcp, IdentifyAllIsAnsweredAfterTheResponseDelay) {
  ctl_eth->send(pn::encode_dcp_identify_request(kCtlMac, 0x1001, std::nullopt, 100));
  run(milliseconds(599));
  EXPECT_TRUE(dcp_answers().empty());
  run(milliseconds(2));
  const auto a = dcp_answers();
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].frame_id, pn::frame_id::kDcpIdentifyResponse);
  EXPECT_EQ(a[0].xid, 0x1001u);
  pn::DcpIdentity id;
  ASSERT_TRUE(pn::identity_from(a[0], id));
  EXPECT_EQ(id.station_name, "echo-1");
  EXPECT_EQ(id.vendor_id, 0x0FFF);
  EXPECT_EQ(id.device_id, 0x0042);
  EXPECT_EQ(id.ip.ip, 0x0A000002u);
}

TEST_F(DeviceDcp, IdentifyByNameAnswersOnlyTheNamedDevice) {
  ctl_eth->send(pn::encode_dcp_identify_request(kCtlMac, 1, std::string("other"), 1));
  run(milliseconds(20));
  EXPECT_TRUE(dcp_answers().empty());
  ctl_eth->send(pn::encode_dcp_identify_request(kCtlMac, 2, std::string("echo-1"), 1));
  run(milliseconds(1));
  EXPECT_EQ(dcp_answers().size(), 1u);
}

// A name of odd length (rt-labs-dev, 11): the Set and the Identify carry
// the padding octet, counted in DCPDataLength (IEC 61158-6-10 DCP, as
// p-net sends it); an Identify that leaves the pad out of DCPDataLength
// (as we sent it before) is answered too.
TEST_F(DeviceDcp, OddLengthNameSetAndIdentifiedWithThePadCountedOrNot) {
  pn::DcpSetRequest s;
  s.station_name = "rt-labs-dev";
  ctl_eth->send(pn::encode_dcp_set_request(kDevMac, kCtlMac, 5, s));
  run(milliseconds(1));
  auto a = dcp_answers();
  ASSERT_EQ(a.size(), 1u);
  std::vector<pn::DcpSetResult> results;
  ASSERT_TRUE(pn::set_results_from(a[0], results));
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].error, pn::dcp::kErrorOk);
  EXPECT_EQ(dev->station_name(), "rt-labs-dev");

  auto counted = pn::encode_dcp_identify_request(kCtlMac, 6, std::string("rt-labs-dev"), 1);
  const std::size_t data_length_at = 14 + 2 + 9;  // low octet of DCPDataLength
  ASSERT_EQ(counted[data_length_at], 16);
  auto uncounted = counted;
  uncounted[data_length_at] = 15;
  for (const auto& request : {counted, uncounted}) {
    ctl_eth->send(request);
    run(milliseconds(1));
    a = dcp_answers();
    ASSERT_EQ(a.size(), 1u);
    pn::DcpIdentity id;
    ASSERT_TRUE(pn::identity_from(a[0], id));
    EXPECT_EQ(id.station_name, "rt-labs-dev");
  }
}

TEST_F(DeviceDcp, SetNameAndIpThenConnectAtTheNewAddress) {
  pn::DcpSetRequest s;
  s.station_name = "conveyor";
  s.ip = pn::DcpIpSuite{0x0A000009, 0xFFFFFF00, 0};
  ctl_eth->send(pn::encode_dcp_set_request(kDevMac, kCtlMac, 5, s));
  run(milliseconds(1));
  const auto a = dcp_answers();
  ASSERT_EQ(a.size(), 1u);
  std::vector<pn::DcpSetResult> results;
  ASSERT_TRUE(pn::set_results_from(a[0], results));
  ASSERT_EQ(results.size(), 2u);
  for (const auto& r : results) EXPECT_EQ(r.error, pn::dcp::kErrorOk);
  EXPECT_EQ(dev->station_name(), "conveyor");
  EXPECT_EQ(dev->ip().host_order, 0x0A000009u);
  // Get answers with the new name.
  const std::array<std::pair<std::uint8_t, std::uint8_t>, 1> opts{
      {{pn::dcp::kOptDevice, pn::dcp::kSubDeviceNameOfStation}}};
  ctl_eth->send(pn::encode_dcp_get_request(kDevMac, kCtlMac, 6, opts));
  run(milliseconds(1));
  const auto g = dcp_answers();
  ASSERT_EQ(g.size(), 1u);
  pn::DcpIdentity id;
  ASSERT_TRUE(pn::identity_from(g[0], id));
  EXPECT_EQ(id.station_name, "conveyor");
  // RPC now at the new address.
  const auto r = call(pn::rpc::kOpConnect, pn::encode_connect_request(connect_request()),
                      pn::Ipv4{0x0A000009});
  ASSERT_TRUE(r.has_value());
  EXPECT_TRUE(r->ndr.status.ok());
  // While the AR is up, name and IP stay (our reading; see pn_device.cpp).
  s.station_name = "renamed";
  s.ip.reset();
  ctl_eth->send(pn::encode_dcp_set_request(kDevMac, kCtlMac, 7, s));
  run(milliseconds(1));
  EXPECT_EQ(dev->station_name(), "conveyor");
}

TEST_F(DeviceDcp, FramesForOtherStationsAreIgnored) {
  pn::DcpSetRequest s;
  s.station_name = "stolen";
  pn::Mac other = kDevMac;
  other[5] ^= 1;
  ctl_eth->send(pn::encode_dcp_set_request(other, kCtlMac, 5, s));
  run(milliseconds(1));
  EXPECT_TRUE(dcp_answers().empty());
  EXPECT_EQ(dev->station_name(), "echo-1");
}

}  // namespace
}  // namespace pn_test

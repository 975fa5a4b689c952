// PnDevice after Connect: records (Write incl. MultipleWrite 0xE040, Read),
// PrmEnd and ApplicationReady (fieldbus-masters.md §1 items 3-5), cyclic
// RT_CLASS_1 exchange and the output frames it takes or drops as p-net's
// CPM does (item 6), its data-hold watchdog, and Release.
#include "plc/profinet/device/record_status.hpp"
#include "test_device_harness.hpp"

namespace pn_test {
namespace {

class DeviceExchange : public DeviceHarness {
 protected:
  void SetUp() override { make_device(); }

  std::optional<Answer> write(std::span<const pn::RecordWrite> recs, bool multiple = false) {
    return call(pn::rpc::kOpWrite, pn::encode_write_request(1, kArUuid, recs, multiple));
  }
};

TEST_F(DeviceExchange, SingleWriteAndReadReachTheModelsRecords) {
  ASSERT_TRUE(connect(connect_request()).ok());
  const pn::RecordWrite w{0, 1, 1, 0x0042, {1, 2, 3}};
  const auto a = write(std::span(&w, 1));
  ASSERT_TRUE(a.has_value());
  EXPECT_TRUE(a->ndr.status.ok());
  EXPECT_EQ(echo->records[0x42], (std::vector<std::uint8_t>{1, 2, 3}));
  pn::RecordRequestHeader rh;
  rh.ar_uuid = kArUuid;
  rh.slot = 1;
  rh.subslot = 1;
  rh.index = 0x0042;
  rh.record_data_length = 240;
  const auto r = call(pn::rpc::kOpRead, pn::encode_read_request(rh));
  ASSERT_TRUE(r.has_value());
  EXPECT_TRUE(r->ndr.status.ok());
  pn::RecordResponseHeader res;
  std::span<const std::uint8_t> data;
  ASSERT_TRUE(pn::decode_read_response(r->args, res, data));
  EXPECT_EQ(std::vector<std::uint8_t>(data.begin(), data.end()),
            (std::vector<std::uint8_t>{1, 2, 3}));
  // An index the model does not have: PNIORW invalid index (record_status.hpp).
  rh.index = 0x0043;
  const auto bad = call(pn::rpc::kOpRead, pn::encode_read_request(rh));
  ASSERT_TRUE(bad.has_value());
  EXPECT_EQ(bad->ndr.status.value(), 0xDE80B000u);
  EXPECT_EQ(pn::record_error_from(bad->ndr.status), io::RecordError::InvalidIndex);
}

// IEC 61158-6-10 MultipleWrite: every record reaches the model in order;
// each gets its own result; a model code (>= 0x100) travels as
// manufacturer-specific status and comes back as the same RecordError.
TEST_F(DeviceExchange, MultipleWriteWritesEveryRecordAndReportsEachResult) {
  ASSERT_TRUE(connect(connect_request()).ok());
  const std::vector<pn::RecordWrite> recs{
      {0, 1, 1, 0x10, {0xA}}, {0, 1, 1, 0x99, {0xB}}, {0, 1, 1, 0x11, {0xC, 0xD}}};
  const auto a = write(recs, true);
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(echo->writes, (std::vector<std::uint16_t>{0x10, 0x11}));
  pn::WriteResponse res;
  ASSERT_TRUE(pn::decode_write_response(a->args, res));
  ASSERT_EQ(res.sub_results.size(), 3u);
  EXPECT_TRUE(res.sub_results[0].status.ok());
  EXPECT_EQ(res.sub_results[1].status.value(), 0xDF821234u);
  EXPECT_TRUE(res.sub_results[2].status.ok());
  EXPECT_EQ(pn::record_error_from(a->ndr.status), static_cast<io::RecordError>(0x1234));
  // A slot the device does not have: PNIORW invalid slot/subslot.
  const pn::RecordWrite nowhere{0, 7, 1, 0x10, {1}};
  const auto b = write(std::span(&nowhere, 1));
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->ndr.status.value(), 0xDF80B200u);
}

TEST_F(DeviceExchange, WriteWithAnotherArUuidIsRefused) {
  ASSERT_TRUE(connect(connect_request()).ok());
  const pn::RecordWrite w{0, 1, 1, 0x42, {1}};
  pn::Uuid other = kArUuid;
  other.data2 ^= 1;
  const auto a = call(pn::rpc::kOpWrite, pn::encode_write_request(1, other, std::span(&w, 1)));
  ASSERT_TRUE(a.has_value());
  EXPECT_FALSE(a->ndr.status.ok());
  EXPECT_TRUE(echo->writes.empty());
}

// PrmEnd answered with 0x8110; then ApplicationReady (0x0112, command
// ApplicationReady) to the controller's UDP 34964, object = its
// CMInitiatorObjectUUID, repeated every 100 ms until answered 0x8112 DONE.
TEST_F(DeviceExchange, ApplicationReadyIsRepeatedUntilAnsweredDone) {
  ASSERT_TRUE(connect(connect_request()).ok());
  pn::ControlBlock c;
  c.block_type = pn::block::kPrmEndReq;
  c.ar_uuid = kArUuid;
  c.session_key = 7;
  const auto a = call(pn::rpc::kOpControl, pn::encode_control(c));
  ASSERT_TRUE(a.has_value());
  ASSERT_TRUE(a->ndr.status.ok());
  pn::ControlBlock res;
  ASSERT_TRUE(pn::decode_control(a->args, res));
  EXPECT_EQ(res.block_type, pn::block::kPrmEndRes);
  EXPECT_EQ(res.command, pn::control::kDone);
  EXPECT_EQ(dev->state(), pn::PnDeviceState::AppReady);

  run(milliseconds(350));
  auto reqs = device_requests();
  ASSERT_EQ(reqs.size(), 4u);  // at 0, 100, 200, 300 ms
  pn::RpcPdu pdu;
  ASSERT_TRUE(pn::decode_rpc(reqs[0], pdu));
  EXPECT_EQ(pdu.header.object, pn::pnio_object_uuid(1, 0x0001, 0x0FFF));
  EXPECT_EQ(pdu.header.interface, pn::kPnioControllerInterface);
  EXPECT_EQ(pdu.header.opnum, pn::rpc::kOpControl);
  pn::NdrRequest ndr;
  ASSERT_TRUE(pn::decode_ndr_request(pdu.body, pdu.header.little_endian, ndr));
  pn::ControlBlock ready;
  ASSERT_TRUE(pn::decode_control(ndr.args, ready));
  EXPECT_EQ(ready.block_type, pn::block::kApplicationReadyReq);
  EXPECT_EQ(ready.command, pn::control::kApplicationReady);
  EXPECT_EQ(ready.ar_uuid, kArUuid);
  EXPECT_EQ(ready.session_key, 7);

  pending_requests = {reqs.back()};
  EXPECT_EQ(answer_app_ready(), 1);
  run(milliseconds(300));
  EXPECT_TRUE(device_requests().empty());  // answered: no more repeats
  // Data exchange only once an output frame came too.
  EXPECT_EQ(dev->state(), pn::PnDeviceState::AppReady);
  const std::array<std::uint8_t, 4> d{9, 8, 7, 6};
  send_output(d);
  run(milliseconds(1));
  EXPECT_EQ(dev->state(), pn::PnDeviceState::DataExchange);
  EXPECT_TRUE(saw(pn::PnDeviceEvent::Kind::DataExchange));
}

TEST_F(DeviceExchange, CyclicDataIsTheModelsBytesBothWays) {
  bring_up();
  const std::array<std::uint8_t, 4> d{0x11, 0x22, 0x33, 0x44};
  send_output(d);
  run(milliseconds(2));
  EXPECT_EQ(echo->last_outputs, (std::vector<std::uint8_t>{0x11, 0x22, 0x33, 0x44}));
  const auto req = connect_request();
  pn::IocrLayout in;
  ASSERT_TRUE(pn::layout_from_iocr(req.iocrs[0], req.expected, in));
  const auto frames = frames_with_id(0xC001);
  ASSERT_FALSE(frames.empty());
  pn::CyclicView v;
  ASSERT_TRUE(pn::decode_cyclic(frames.back(), in.c_sdu_length, v));
  const auto got = pn::io_data(v.c_sdu, *in.find(0, 1, 1));
  EXPECT_EQ(std::vector<std::uint8_t>(got.begin(), got.end()),
            (std::vector<std::uint8_t>{0xEE, 0xDD, 0xCC, 0xBB}));
  // The counter advances by SendClockFactor x ReductionRatio per frame.
  pn::CyclicView prev;
  ASSERT_TRUE(pn::decode_cyclic(frames[frames.size() - 2], in.c_sdu_length, prev));
  EXPECT_EQ(static_cast<std::uint16_t>(v.header.cycle_counter - prev.header.cycle_counter), 32);
}

// p-net pf_cpm.c: a controller frame is taken only with the controller's
// source MAC, the exact length, TransferStatus 0, an advanced cycle counter
// and DataValid; each dropped frame is counted under its reason and its
// data never reaches the model.
TEST_F(DeviceExchange, OutputFramesAreTakenOnlyAsPnetTakesThem) {
  bring_up();
  const std::array<std::uint8_t, 4> good{1, 1, 1, 1};
  const std::array<std::uint8_t, 4> bad{0xBA, 0xD0, 0xBA, 0xD0};
  send_output(good);
  run(milliseconds(1));
  const auto before = dev->acceptance().accepted();

  pn::Mac stranger = kCtlMac;
  stranger[5] = 0x77;
  ctl_eth->send(output_frame(bad, counter_ + 32, pn::data_status::kGood, 0, stranger));
  auto longer = output_frame(bad, counter_ + 32);
  longer.push_back(0);
  ctl_eth->send(longer);
  ctl_eth->send(output_frame(bad, counter_ + 32, pn::data_status::kGood, 1));
  ctl_eth->send(output_frame(bad, counter_));        // counter not advanced (duplicate)
  ctl_eth->send(output_frame(bad, counter_ - 100));  // went back
  ctl_eth->send(
      output_frame(bad, counter_ + 32, pn::data_status::kGood & ~pn::data_status::kDataValid));
  run(milliseconds(1));

  using R = pn::OutputReject;
  EXPECT_EQ(dev->acceptance().rejected(R::WrongSource), 1u);
  EXPECT_EQ(dev->acceptance().rejected(R::WrongLength), 1u);
  EXPECT_EQ(dev->acceptance().rejected(R::TransferStatus), 1u);
  EXPECT_EQ(dev->acceptance().rejected(R::CounterNotAdvanced), 2u);
  EXPECT_EQ(dev->acceptance().rejected(R::DataInvalid), 1u);
  EXPECT_EQ(dev->acceptance().accepted(), before);
  EXPECT_EQ(echo->last_outputs, (std::vector<std::uint8_t>{1, 1, 1, 1}));
  // The counter may jump up to 61440 ahead (p-net pf_cpm_check_cycle).
  ctl_eth->send(output_frame(good, static_cast<std::uint16_t>(counter_ + 61440)));
  run(milliseconds(1));
  EXPECT_EQ(dev->acceptance().accepted(), before + 1);
}

TEST(OutputAcceptance, CycleCounterWindowOfPnet) {
  // The vectors of p-net's CpmCheckCycle unit test, previous counter 0x4000.
  pn::OutputAcceptance a;
  const pn::Mac m{2, 0, 0, 0, 0, 1};
  auto take = [&](std::uint16_t prev, std::uint16_t now) {
    a.start(m, 60);
    EXPECT_FALSE(a.check({m, 60, prev, 0x35, 0}).has_value());
    return !a.check({m, 60, now, 0x35, 0}).has_value();
  };
  EXPECT_TRUE(take(0x4000, 0x0000));
  EXPECT_TRUE(take(0x4000, 0x3000));
  EXPECT_FALSE(take(0x4000, 0x3001));
  EXPECT_FALSE(take(0x4000, 0x3FFF));
  EXPECT_FALSE(take(0x4000, 0x4000));
  EXPECT_TRUE(take(0x4000, 0x4001));
  EXPECT_TRUE(take(1, 2));
  EXPECT_FALSE(take(1, 0xFFFF));
  EXPECT_FALSE(take(1, 1));
}

// The device's own data-hold watchdog: DataHoldFactor (3) x 1 ms without a
// taken output frame drops the AR: the model hears io_connection_lost() and
// gets zero outputs, and the device waits for the next Connect.
TEST_F(DeviceExchange, DataHoldExpiryDropsTheArAndZeroesTheOutputs) {
  bring_up();
  const std::array<std::uint8_t, 4> d{5, 5, 5, 5};
  send_output(d);
  run(milliseconds(2));  // 2 ms since the last frame: still within 3 ms
  EXPECT_EQ(dev->state(), pn::PnDeviceState::DataExchange);
  EXPECT_EQ(echo->lost, 0);
  run(milliseconds(2));  // now 4 ms: expired
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Idle);
  EXPECT_EQ(echo->lost, 1);
  EXPECT_EQ(dev->counters().data_hold_expired, 1u);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().kind, pn::PnDeviceEvent::Kind::Lost);
  EXPECT_EQ(events.back().end, pn::ArEnd::DataHoldExpired);
  run(milliseconds(3));
  EXPECT_EQ(echo->last_outputs, (std::vector<std::uint8_t>{0, 0, 0, 0}));
  controller_frames();
  run(milliseconds(3));
  EXPECT_TRUE(frames_with_id(0xC001).empty());  // no more input frames
  // And back: a new Connect is accepted.
  EXPECT_TRUE(connect(connect_request()).ok());
}

TEST_F(DeviceExchange, StopAnsweringFaultLetsTheControllerSideTimeOut) {
  bring_up();
  dev->faults().silent = true;
  controller_frames();
  for (int i = 0; i < 5; ++i) {
    const std::array<std::uint8_t, 4> d{1, 2, 3, 4};
    send_output(d);
    run(milliseconds(1));
  }
  EXPECT_TRUE(controller_frames().empty());
  // A pulled plug hears nothing either: its own watchdog drops the AR.
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Idle);
  EXPECT_EQ(echo->lost, 1);
}

TEST_F(DeviceExchange, DropAndDelayFaultsActOnTheInputFrames) {
  bring_up();
  controller_frames();
  dev->faults().drop_cyclic = 3;
  for (int i = 0; i < 5; ++i) {
    const std::array<std::uint8_t, 4> d{1, 2, 3, 4};
    send_output(d);
    run(milliseconds(1));
  }
  EXPECT_EQ(dev->counters().frames_dropped_by_fault, 3u);
  EXPECT_EQ(frames_with_id(0xC001).size(), 2u);
  dev->faults().delay_cyclic = milliseconds(10);
  for (int i = 0; i < 5; ++i) {
    const std::array<std::uint8_t, 4> d{1, 2, 3, 4};
    send_output(d);
    run(milliseconds(1));
  }
  EXPECT_TRUE(frames_with_id(0xC001).empty());  // all still held back
  dev->faults().delay_cyclic = nanoseconds(0);
  for (int i = 0; i < 10; ++i) {
    const std::array<std::uint8_t, 4> d{1, 2, 3, 4};
    send_output(d);
    run(milliseconds(1));
  }
  EXPECT_EQ(frames_with_id(0xC001).size(), 15u);  // 5 late ones + 10 on time
}

// Release (opnum 1, IODReleaseReq 0x0114) answered 0x8114 DONE; the AR ends
// without io_connection_lost().
TEST_F(DeviceExchange, ReleaseEndsTheAr) {
  bring_up();
  pn::ControlBlock c;
  c.block_type = pn::block::kReleaseReq;
  c.ar_uuid = kArUuid;
  c.session_key = 7;
  c.command = pn::control::kRelease;
  const auto a = call(pn::rpc::kOpRelease, pn::encode_control(c));
  ASSERT_TRUE(a.has_value());
  ASSERT_TRUE(a->ndr.status.ok());
  pn::ControlBlock res;
  ASSERT_TRUE(pn::decode_control(a->args, res));
  EXPECT_EQ(res.block_type, pn::block::kReleaseRes);
  EXPECT_EQ(res.command, pn::control::kDone);
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Idle);
  EXPECT_EQ(echo->lost, 0);
  EXPECT_TRUE(saw(pn::PnDeviceEvent::Kind::Released));
}

TEST_F(DeviceExchange, ArNeverStartedTimesOutAfterTheActivityTimeout) {
  auto req = connect_request();
  req.ar.activity_timeout_factor = 10;  // 1 s
  ASSERT_TRUE(connect(req).ok());
  run(milliseconds(990));
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Parameterizing);
  run(milliseconds(20));
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Idle);
  EXPECT_EQ(events.back().end, pn::ArEnd::StartupTimeout);
}

}  // namespace
}  // namespace pn_test

// Answers to acyclic requests become visible only at a scan's latch (the
// DeviceLink's deferred delivery): never in the middle of a scan, and in the
// scan a recording logs them, so a real-time recording replays exactly.
#include <gtest/gtest.h>

#include <array>

#include "plc/debug/debugger.hpp"
#include "plc/debug/recording.hpp"
#include "plc/io/device_link.hpp"
#include "test_helpers.hpp"
#include "test_programs.hpp"

using namespace plc;

namespace {

struct Owner {
  explicit Owner(int o) { io::DeviceLink::set_current_owner(o); }
  ~Owner() { io::DeviceLink::set_current_owner(-1); }
};

int deliver(io::DeviceLink& link, int owner) {
  int n = 0;
  link.deliver_answered(owner, [&n](const io::RecordRequest&) { ++n; });
  return n;
}

}  // namespace

TEST(AcyclicDelivery, DeferredAnswerWaitsForTheOwnersLatch) {
  io::DeviceLink link;
  link.set_state(io::DeviceState::Online);
  link.set_deferred(true);
  io::RecordRequest r;
  r.prepare_read(7);
  {
    Owner in_task(1);
    ASSERT_TRUE(link.submit(r));
  }
  ASSERT_EQ(link.pop(), &r);  // the plugin takes it and answers
  r.buffer()[0] = 0x5A;
  r.complete(1);
  EXPECT_EQ(r.status(), io::RecordStatus::Queued) << "parked, not yet visible";
  EXPECT_EQ(deliver(link, 0), 0) << "another task's latch does not deliver it";
  EXPECT_EQ(r.status(), io::RecordStatus::Queued);
  EXPECT_EQ(deliver(link, 1), 1);
  EXPECT_EQ(r.status(), io::RecordStatus::Done);
  ASSERT_EQ(r.data().size(), 1u);
  EXPECT_EQ(r.data()[0], 0x5A);
  EXPECT_EQ(deliver(link, 1), 0) << "delivered once";
}

TEST(AcyclicDelivery, RefusalsAreImmediateAndErrorsAreDeferred) {
  io::DeviceLink link;
  link.set_deferred(true);  // offline
  io::RecordRequest r;
  r.prepare_read(1);
  EXPECT_FALSE(link.submit(r));
  EXPECT_EQ(r.status(), io::RecordStatus::Error) << "refusal is the answer, at once";
  EXPECT_EQ(r.error(), io::RecordError::NotReachable);
  link.set_state(io::DeviceState::Online);
  EXPECT_FALSE(link.submit(r)) << "the state FBs see changes only at a latch";
  link.latch_state();
  r.reset();
  ASSERT_TRUE(link.submit(r));
  link.pop()->fail(io::RecordError::InvalidIndex);
  EXPECT_EQ(r.status(), io::RecordStatus::Queued);
  EXPECT_EQ(deliver(link, -1), 1);
  EXPECT_EQ(r.status(), io::RecordStatus::Error);
  EXPECT_EQ(r.error(), io::RecordError::InvalidIndex);
}

TEST(AcyclicDelivery, UndeferredLinkAnswersAtOnce) {
  // Unit tests drive FBs against a bare SimDevice: no runtime, no latch.
  io::DeviceLink link;
  link.set_state(io::DeviceState::Online);
  io::RecordRequest r;
  r.prepare_write(3, std::array<std::uint8_t, 2>{1, 2});
  ASSERT_TRUE(link.submit(r));
  link.pop()->complete(2);
  EXPECT_EQ(r.status(), io::RecordStatus::Done);
}

TEST(AcyclicDelivery, FullTrackingRefusesInsteadOfLosingAnAnswer) {
  io::DeviceLink link;
  link.set_state(io::DeviceState::Online);
  link.set_deferred(true);
  std::array<io::RecordRequest, 4 * io::DeviceLink::kQueueDepth + 1> rs;
  std::size_t taken = 0;
  for (auto& r : rs) {
    r.prepare_read(1);
    if (link.submit(r)) ++taken;
    while (io::RecordRequest* p = link.pop()) p->complete(0);  // answered, not delivered
  }
  EXPECT_EQ(taken, 4 * io::DeviceLink::kQueueDepth);
  EXPECT_EQ(rs.back().error(), io::RecordError::QueueFull);
  EXPECT_EQ(deliver(link, -1), static_cast<int>(taken));
}

// Real time: the sim plugin's thread answers whenever it likes, yet no
// answer shows mid-scan, and the recording replays with identical outputs.
TEST(AcyclicDelivery, RealTimeRecordingOfAcyclicTrafficReplaysExactly) {
  const CellConfig cfg = parse_cell_config(R"(
tasks: [{name: main, period: 1ms, programs: [Poll]}]
programs: [{name: Poll, type: RecordPoller}]
plugins: [{name: sim, params: {step: 250us}}]
devices:
  - {name: echo, plugin: sim, model: loopback, input: "%IB0", output: "%QB0", params: {size: 8}}
)",
                                           "rt_acyclic.yaml");
  const std::string rec = plctest::temp_path("rt_acyclic.rec");
  DINT answers = 0;
  {
    Runtime rt(cfg);
    debug::Recorder recorder(rt, rec);
    rt.run(io::ClockMode::RealTime, std::chrono::milliseconds(600));
    recorder.close();
    auto* poll = static_cast<plctest::RecordPoller*>(rt.program("Poll"));
    answers = poll->answers;
    EXPECT_GT(answers, 100) << "the bus answered throughout";
    EXPECT_EQ(poll->midscan_changes, 0) << "an answer became visible during a scan";
  }
  debug::Debugger::Options o;
  o.replay_file = rec;
  o.span = std::chrono::minutes(1);
  debug::Debugger replay([&cfg] { return std::make_unique<Runtime>(cfg); }, o);
  const std::string out = replay.execute("continue");
  EXPECT_NE(out.find("the recording has ended"), std::string::npos) << out;
  EXPECT_NE(out.find(" 0 output mismatch(es)"), std::string::npos) << out;
  auto* poll = static_cast<plctest::RecordPoller*>(replay.runtime().program("Poll"));
  EXPECT_EQ(poll->answers, answers) << "the replay saw every answer in the same scan";
  std::remove(rec.c_str());
}

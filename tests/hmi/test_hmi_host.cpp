// plcrun's HMI host against a bridge that writes anything into the command
// ring (issue 22, "Process isolation": a malicious or crashed plchmi can at
// worst fill the ring; it cannot make plcrun parse text, block or crash).
// Records are pushed into the ring as a taken-over plchmi would, the host
// serves one round, and each gets its refusal with nothing applied; the
// access the cell's patterns give is checked again by index in plcrun.
// Lockstep, virtual time.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstring>
#include <fstream>

#include "hmi_test_cell.hpp"
#include "plc/hmi/host_commands.hpp"

using namespace plc;
using plc::hmi::ipc::CommandRecord;
using plc::hmi::ipc::Reason;
using plc::hmi::ipc::ReplyRecord;
using plc::hmi::ipc::Verb;
using plc::hmi::ipc::WireOperand;
using plctest::HmiCell;

namespace {

// A fake bridge: the raw rings of the host's shared memory.
struct FakeBridge {
  explicit FakeBridge(HmiCell& h) : h(h), view(h.host->regions().view()) {}
  HmiCell& h;
  std::unique_ptr<hmi::ipc::Regions> view;
  std::uint32_t token = 1000;

  std::uint64_t generation() const { return view->state().generation.load(); }
  std::uint32_t index(const std::string& path) const {
    const auto d = h.bridge->description();
    for (int i = 0; i < d.n; ++i)
      if (d.vars[std::size_t(i)].path == path) return std::uint32_t(i);
    ADD_FAILURE() << "no " << path;
    return 0;
  }
  CommandRecord record(Verb v) {
    CommandRecord r{};
    r.token = ++token;
    r.verb = std::uint8_t(v);
    r.generation = generation();
    r.count = 1;
    return r;
  }
  static WireOperand var(std::uint32_t i) {
    WireOperand o;
    o.kind = WireOperand::Var;
    o.value = i;
    return o;
  }
  // Pushes r, lets plcrun serve one round, returns its reply.
  ReplyRecord send(const CommandRecord& r) {
    EXPECT_TRUE(view->commands().push(r));
    h.host->round();
    ReplyRecord out{};
    EXPECT_EQ(view->replies().pop(out), hmi::ipc::Ring<ReplyRecord>::Pop::Got);
    EXPECT_EQ(out.token, r.token);
    return out;
  }
};

std::string text(const ReplyRecord& r) {
  return std::string(r.text, strnlen(r.text, sizeof r.text));
}

}  // namespace

TEST(HmiHost, RecordsOutsideWhatTheCellAllowsAreRefusedWithTheirReason) {
  HmiCell h;
  h.dbg->step(1);
  FakeBridge b(h);
  const std::string step = h.value_of("Tank.step");
  const std::string level = h.value_of("Tank.high_level");
  struct Row {
    CommandRecord r;
    Reason reason;
    const char* why;
  };
  std::vector<Row> rows;
  auto add = [&](CommandRecord r, Reason reason, const char* why) {
    rows.push_back({r, reason, why});
  };
  {
    auto r = b.record(Verb::None);
    add(r, Reason::Malformed, "verb 0");
    r.verb = 200;
    add(r, Reason::Malformed, "verb 200");
  }
  {
    auto r = b.record(Verb::Write);
    r.target = FakeBridge::var(b.index("Tank.high_level"));
    r.generation = 7;
    add(r, Reason::Stale, "generation 7");
  }
  {
    auto r = b.record(Verb::Write);  // not writable: the patterns, checked again here
    r.target = FakeBridge::var(b.index("Tank.step"));
    r.value[0] = 7;
    add(r, Reason::NotWritable, "Tank.step is not writable");
  }
  {
    auto r = b.record(Verb::Write);
    r.target = FakeBridge::var(1'000'000);
    add(r, Reason::BadOperand, "beyond the cell's");
    r.target.kind = WireOperand::Address;
    r.target.value = 0;
    add(r, Reason::NotWritable, "not a variable");
  }
  {
    auto r = b.record(Verb::Force);
    r.target = FakeBridge::var(b.index("Tank.high_level"));  // writable, not forceable
    add(r, Reason::NotForceable, "not forceable");
    r.verb = std::uint8_t(Verb::Unforce);
    add(r, Reason::NotForceable, "not forceable");
    r.restore = 2;
    add(r, Reason::Malformed, "restore flag 2");
  }
  for (Verb v :
       {Verb::Pause, Verb::Step, Verb::Continue, Verb::Break, Verb::Delete, Verb::DeleteAll})
    add(b.record(v), Reason::NoStops, "stop_commands is false");
  {
    auto r = b.record(Verb::Read);
    add(r, Reason::Malformed, "read of 0 variables");
    r.n_operands = 33;
    add(r, Reason::Malformed, "read of 33");
    r.n_operands = 1;
    r.operands[0] = FakeBridge::var(b.index("Tank.level"));
    r.operands[0].bit = 3;
    add(r, Reason::Malformed, "address fields set");
    r.operands[0] = WireOperand{WireOperand::Address, 0, 2, 0, 1'000'000};
    add(r, Reason::BadOperand, "lies outside the image");
    r.operands[0] = WireOperand{WireOperand::Address, 9, 0, 0, 0};
    add(r, Reason::Malformed, "address operand out of range");
    r.operands[0] = WireOperand{7, 0, 0, 0, 0};
    add(r, Reason::Malformed, "operand kind 7");
  }
  for (const Row& row : rows) {
    const ReplyRecord rep = b.send(row.r);
    EXPECT_EQ(rep.reason, std::uint8_t(row.reason)) << row.why << ": " << text(rep);
    EXPECT_NE(text(rep).find(row.why), std::string::npos) << text(rep);
  }
  const auto& host = h.host->regions().state().host;
  EXPECT_EQ(host.refused.load(), rows.size());
  EXPECT_EQ(host.served.load(), 0U);
  h.dbg->step(3);
  EXPECT_EQ(h.value_of("Tank.step"), step);
  EXPECT_EQ(h.value_of("Tank.high_level"), level);
  EXPECT_EQ(h.dbg->execute("forces"), "no forces\n");
}

// The bytes of a value get the debugger's checks: a BOOL byte other than
// 0/1 (which a text literal cannot even express) is refused.
TEST(HmiHost, RawValuesThatNoLiteralGivesAreRefusedByTheDebugger) {
  HmiCell h;
  h.dbg->step(1);
  FakeBridge b(h);
  auto r = b.record(Verb::Force);
  r.target = FakeBridge::var(b.index("Tank.enable"));
  r.value[0] = 7;
  const ReplyRecord rep = b.send(r);
  EXPECT_EQ(rep.reason, std::uint8_t(Reason::Refused)) << text(rep);
  EXPECT_NE(text(rep).find("not a BOOL"), std::string::npos) << text(rep);
  EXPECT_EQ(h.dbg->execute("forces"), "no forces\n");
  r.value[0] = 0;
  EXPECT_EQ(b.send(r).reason, std::uint8_t(Reason::Ok));
  EXPECT_EQ(h.dbg->forced(), std::vector<std::string>{"Tank.enable"});
}

// Condition code from the ring is validated and bound by plcrun, never
// parsed; what does not validate is refused naming why.
TEST(HmiHost, BreakpointCodeIsValidatedBeforeItIsBound) {
  HmiCell h(std::string(plctest::kHmiSection) + "  stop_commands: true\n");
  h.dbg->step(1);
  FakeBridge b(h);
  using Op = debug::ConditionCode::Op;
  auto r = b.record(Verb::Break);
  r.n_operands = 1;
  r.operands[0] = FakeBridge::var(b.index("Tank.step"));
  r.n_consts = 1;
  r.consts[0].bits = 3;
  r.n_instrs = 3;
  r.instrs[0] = {std::uint8_t(Op::Var), 0, 0};
  r.instrs[1] = {std::uint8_t(Op::Const), 0, 0};
  r.instrs[2] = {std::uint8_t(Op::Eq), 0, 0};
  auto bad = r;
  bad.instrs[2].op = 99;
  auto rep = b.send(bad);
  EXPECT_EQ(rep.reason, std::uint8_t(Reason::BadCode));
  EXPECT_NE(text(rep).find("unknown op code 99"), std::string::npos) << text(rep);
  bad = r;
  bad.instrs[0].index = 5;
  EXPECT_NE(text(b.send(bad)).find("operand index out of range"), std::string::npos);
  bad = r;
  bad.n_instrs = 300;
  EXPECT_EQ(b.send(bad).reason, std::uint8_t(Reason::Malformed));
  bad = r;
  bad.consts[0].real = 2;
  EXPECT_EQ(b.send(bad).reason, std::uint8_t(Reason::Malformed));
  EXPECT_EQ(h.dbg->execute("breaks"), "no breakpoints\n");
  rep = b.send(r);
  EXPECT_EQ(rep.reason, std::uint8_t(Reason::Ok)) << text(rep);
  EXPECT_EQ(text(rep), "breakpoint 1: Tank.step = 3\n");
}

// A producer position that is not plausible makes the host skip to it and
// count it; a ring filled to the brim is served a ring's worth per round.
TEST(HmiHost, ImplausibleRingPositionsAreSkippedAndCounted) {
  HmiCell h;
  FakeBridge b(h);
  b.view->control().command_head.store(123456789);
  h.host->round();
  EXPECT_EQ(h.host->regions().state().host.skipped.load(), 1U);
  // Full: every record is answered, none applied.
  for (std::uint32_t i = 0; i < hmi::ipc::kCommandCapacity; ++i)
    ASSERT_TRUE(b.view->commands().push(b.record(Verb::Pause)));
  EXPECT_FALSE(b.view->commands().push(b.record(Verb::Pause)));
  EXPECT_EQ(h.host->round(), int(hmi::ipc::kCommandCapacity));
  ReplyRecord out{};
  int replies = 0;
  while (b.view->replies().pop(out) == hmi::ipc::Ring<ReplyRecord>::Pop::Got) ++replies;
  // The reply ring holds fewer than a full command ring: the rest is counted lost.
  EXPECT_EQ(replies + int(h.host->regions().state().host.replies_lost.load()),
            int(hmi::ipc::kCommandCapacity));
}

// `unforce all` from the HMI releases only the forces on variables the
// HMI may force; the console's force on anything else stays (issue 22).
TEST(HmiHost, UnforceAllFromTheHmiReleasesOnlyWhatTheHmiMayForce) {
  HmiCell h;
  h.dbg->step(1);
  ASSERT_TRUE(h.dbg->force("Tank.step", "2").ok);        // the console: not HMI-forceable
  ASSERT_TRUE(h.dbg->force("Tank.enable", "FALSE").ok);  // HMI-forceable
  softplc_hmi::command_t c{};
  c.request_id = 1;
  c.client = "test";
  c.verb = "unforce";
  c.args = {"all"};
  c.n_args = 1;
  h.replies.clear();
  h.bridge->transport().publish(h.bridge->channels().cmd, &c);
  h.bridge->service();
  ASSERT_EQ(h.replies.size(), 1U);
  EXPECT_TRUE(h.replies[0].ok) << h.replies[0].refusal;
  EXPECT_NE(h.replies[0].text.find("unforced Tank.enable"), std::string::npos);
  EXPECT_NE(h.replies[0].text.find("kept Tank.step"), std::string::npos) << h.replies[0].text;
  EXPECT_EQ(h.dbg->forced(), std::vector<std::string>{"Tank.step"});
  // Again: nothing the HMI may release is left.
  h.replies.clear();
  c.request_id = 2;
  h.bridge->transport().publish(h.bridge->channels().cmd, &c);
  h.bridge->service();
  ASSERT_EQ(h.replies.size(), 1U);
  EXPECT_FALSE(h.replies[0].ok);
  EXPECT_EQ(h.dbg->forced(), std::vector<std::string>{"Tank.step"});
}

// By construction the scan thread never waits for the HMI: in virtual time
// the scans run on this thread, and across thousands of scans with the
// bridge asking for a snapshot at every one (the worst case), and then with
// a bridge that never comes back, this thread is never switched out
// voluntarily (no sleep, no lock wait, no blocking system call).
TEST(HmiHost, TheScanThreadNeverWaitsForTheBridge) {
  HmiCell h;
  h.dbg->step(1);
  h.bridge->service();
  auto voluntary = [] {
    rusage u{};
    getrusage(RUSAGE_THREAD, &u);
    return u.ru_nvcsw;
  };
  auto& rt = h.dbg->runtime();
  const long before = voluntary();
  std::uint64_t scans = 0;
  for (int i = 0; i < 5000; ++i) {
    // What the bridge does at each tick: ask for the next scan's values.
    auto& req = h.host->regions().control().requests[0];
    req.store(req.load() + 1);
    scans += rt.step_scan() ? 1 : 0;
  }
  // The bridge gone: its last request stays unanswered by nobody.
  for (int i = 0; i < 5000; ++i) scans += rt.step_scan() ? 1 : 0;
  const long after = voluntary();
  EXPECT_EQ(scans, 10000U);
  EXPECT_EQ(after - before, 0) << "the scan thread blocked " << after - before << " time(s)";
}

// One scan as data (DESIGN.md): consistent private copies per task, merge of
// changed bits only, devices latched/published by their task.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "plc/io/sim_device.hpp"
#include "plc/io/sim_plugin.hpp"
#include "test_helpers.hpp"
#include "test_programs.hpp"

using namespace plc;

TEST(ScanSemantics, TwoTasksShareAnOutputByteWithoutClobberingBits) {
  auto rt = plctest::make_runtime(R"(
tasks:
  - {name: a, period: 1ms, programs: [A]}
  - {name: b, period: 3ms, programs: [B]}
programs:
  - {name: A, type: BitWriter, bind: {mine: "%QX8.0"}}
  - {name: B, type: BitWriter, bind: {mine: "%QX8.5"}}
)");
  auto* a = static_cast<plctest::BitWriter*>(rt->program("A"));
  auto* b = static_cast<plctest::BitWriter*>(rt->program("B"));
  rt->start(io::ClockMode::Virtual);
  rt->tick();
  EXPECT_EQ(rt->image().area(io::Area::Output)[8], 0x21);
  a->value = false;
  rt->tick();
  rt->tick();
  EXPECT_EQ(rt->image().area(io::Area::Output)[8], 0x20) << "B's bit survives A's scans";
  b->value = false;
  a->value = true;
  rt->tick();  // t=3ms: A then B
  EXPECT_EQ(rt->image().area(io::Area::Output)[8], 0x01);
  rt->finish();
}

TEST(ScanSemantics, DeviceInputsArriveThroughTheImageOneStepLater) {
  auto rt = plctest::make_runtime(R"(
tasks: [{name: main, period: 1ms, programs: [Loop]}]
programs: [{name: Loop, type: LoopCounter}]
plugins: [{name: sim}]
devices: [{name: echo, plugin: sim, model: loopback, input: "%IB0", output: "%QB0", params: {size: 4}}]
)");
  auto* p = static_cast<plctest::LoopCounter*>(rt->program("Loop"));
  rt->start(io::ClockMode::Virtual);
  rt->tick();
  EXPECT_EQ(p->count, 1);
  EXPECT_EQ(p->echoed, 0);
  for (int i = 0; i < 99; ++i) rt->tick();
  EXPECT_EQ(p->count, 100);
  EXPECT_EQ(p->echoed, 99);
  EXPECT_EQ(rt->vars().find("Loop.from_dev")->address->to_string(), "%ID0");
  rt->finish();
}

TEST(ScanSemantics, ProgramsRunInTheOrderTheirTaskListsThem) {
  auto rt = plctest::make_runtime(R"(
tasks: [{name: main, period: 1ms, programs: [Second, First]}]
programs:
  - {name: First, type: ReleaseLog}
  - {name: Second, type: ReleaseLog}
)");
  rt->run(io::ClockMode::Virtual, std::chrono::milliseconds(3));
  auto* first = static_cast<plctest::ReleaseLog*>(rt->program("First"));
  auto* second = static_cast<plctest::ReleaseLog*>(rt->program("Second"));
  for (int k = 0; k < 3; ++k) EXPECT_LT(second->order[k], first->order[k]);
}

TEST(ScanSemantics, SilentDeviceGoesOfflineAndKeepsLastInputs) {
  auto rt = plctest::make_runtime(R"(
tasks: [{name: main, period: 1ms, programs: [Loop]}]
programs: [{name: Loop, type: LoopCounter}]
plugins: [{name: sim}]
devices: [{name: echo, plugin: sim, model: first_order, input: "%IB0", output: "%QB0"}]
)");
  rt->run(io::ClockMode::Virtual, std::chrono::milliseconds(5));
  auto* sim = static_cast<io::SimPlugin*>(rt->plugin("sim"));
  EXPECT_EQ(sim->device("echo")->link().state(), io::DeviceState::Online);
}

TEST(ScanSemantics, RealTimeSmokeRunsOnTheGrid) {
  // Real time is measured in benchmarks, not asserted; this only checks that
  // the threads run, count and stop cleanly with outputs safe.
  auto rt = plctest::make_runtime(R"(
tasks: [{name: main, period: 2ms, programs: [Loop]}]
programs: [{name: Loop, type: LoopCounter}]
plugins: [{name: sim}]
devices: [{name: echo, plugin: sim, model: loopback, input: "%IB0", output: "%QB0", params: {size: 4}}]
)");
  const auto w0 = std::chrono::steady_clock::now();
  rt->run(io::ClockMode::RealTime, std::chrono::milliseconds(100));
  const auto took = std::chrono::steady_clock::now() - w0;
  const TaskStats t = rt->task("main")->stats.snapshot();
  EXPECT_GT(t.scans, 0u);
  // The overrun policy: one release per point of the 2 ms grid, missed ones
  // skipped, never run back to back. Counted against the time the run
  // really took (a loaded machine or a sanitizer may end it late, which
  // adds grid points, not bursts), not against the nominal 100 ms.
  const auto grid = std::uint64_t(took / std::chrono::milliseconds(2)) + 1;
  EXPECT_LE(t.scans + t.skipped, grid) << "never more releases than the grid holds";
  EXPECT_EQ(t.latency_ns.count(), t.scans);
  EXPECT_EQ(std::uint64_t(static_cast<plctest::LoopCounter*>(rt->program("Loop"))->count), t.scans)
      << "the program ran once per scan";
  auto* sim = static_cast<io::SimPlugin*>(rt->plugin("sim"));
  for (auto b : sim->device("echo")->outputs()) EXPECT_EQ(b, 0) << "safe outputs after stop";
}

// Issue 23: in virtual time the sim plugin hands the scan its devices'
// buffers (Plugin::direct_io), and the scan copies them itself with no
// call into the plugin per device; in real time (a stepping thread, a
// mutex) it does not, and every latch and publish goes through the plugin.
TEST(ScanSemantics, SimPluginHandsTheScanItsBuffersInVirtualTimeOnly) {
  const char* cell = R"(
tasks: [{name: main, period: 1ms, programs: [Loop]}]
programs: [{name: Loop, type: LoopCounter}]
plugins: [{name: sim}]
devices: [{name: echo, plugin: sim, model: loopback, input: "%IB0", output: "%QB0", params: {size: 4}}]
)";
  {
    auto rt = plctest::make_runtime(cell);
    auto* sim = static_cast<io::SimPlugin*>(rt->plugin("sim"));
    EXPECT_FALSE(sim->direct_io(0)) << "not before start: tests may drive it from threads";
    rt->start(io::ClockMode::Virtual);
    const DeviceRuntime& d = rt->devices()[0];
    EXPECT_EQ(d.direct_in, sim->device("echo")->inputs().data());
    EXPECT_EQ(d.direct_out, sim->device("echo")->outputs().data());
    // The bytes still go both ways: the loopback echoes the program's
    // counter one step later (as in DeviceInputsArriveThroughTheImage...).
    for (int i = 0; i < 10; ++i) rt->tick();
    auto* p = static_cast<plctest::LoopCounter*>(rt->program("Loop"));
    EXPECT_EQ(p->echoed, p->count - 1);
    rt->finish();
  }
  {
    auto rt = plctest::make_runtime(cell);
    auto* sim = static_cast<io::SimPlugin*>(rt->plugin("sim"));
    sim->start(io::ClockMode::RealTime);
    EXPECT_FALSE(sim->direct_io(0));
    sim->stop();
  }
}

// Issue 23: the scan copies a direct device's bytes itself, inline for up
// to 64 bytes (two overlapping fixed-size copies) and with memcpy above.
// Every size class, and each one's edges, must carry exactly its bytes both
// ways: %Q -> device at the publish, device -> %I at the next latch, with
// the gap bytes between the devices left alone.
TEST(ScanSemantics, DirectDevicesOfEverySizeCarryExactlyTheirBytes) {
  const std::size_t sizes[] = {1,  2,  3,  4,  5,  7,  8,  9,  15, 16, 17,
                               24, 31, 32, 33, 40, 47, 48, 63, 64, 65, 100};
  std::string cell = R"(
image: {inputs: 1024, outputs: 1024, memory: 16}
tasks: [{name: main, period: 1ms, programs: [Loop]}]
programs: [{name: Loop, type: LoopCounter}]
plugins: [{name: sim}]
devices:
)";
  std::vector<std::size_t> at;  // byte offset of each device, a zero byte before and after
  std::size_t next = 8;         // LoopCounter uses %QD0 and %ID0
  for (std::size_t k = 0; k < std::size(sizes); ++k) {
    at.push_back(next);
    cell += "  - {name: d" + std::to_string(k) + ", plugin: sim, model: loopback, input: \"%IB" +
            std::to_string(next) + "\", output: \"%QB" + std::to_string(next) +
            "\", params: {size: " + std::to_string(sizes[k]) + "}}\n";
    next += sizes[k] + 1;
  }
  auto rt = plctest::make_runtime(cell);
  rt->start(io::ClockMode::Virtual);
  rt->tick();
  const auto pattern = [](std::size_t k, std::size_t j) {
    return static_cast<std::uint8_t>(0x80 | ((k * 7 + j) & 0x7F));
  };
  auto q = rt->image().area(io::Area::Output);
  for (std::size_t k = 0; k < std::size(sizes); ++k)
    for (std::size_t j = 0; j < sizes[k]; ++j) q[at[k] + j] = pattern(k, j);
  rt->tick();  // the publish hands %Q to the devices
  rt->tick();  // the loopbacks echo it, the latch brings it into %I
  auto* sim = static_cast<io::SimPlugin*>(rt->plugin("sim"));
  const auto in = rt->image().area(io::Area::Input);
  for (std::size_t k = 0; k < std::size(sizes); ++k) {
    const auto out = sim->device("d" + std::to_string(k))->outputs();
    ASSERT_EQ(out.size(), sizes[k]);
    for (std::size_t j = 0; j < sizes[k]; ++j) {
      EXPECT_EQ(out[j], pattern(k, j)) << "published, size " << sizes[k] << " byte " << j;
      EXPECT_EQ(in[at[k] + j], pattern(k, j)) << "latched, size " << sizes[k] << " byte " << j;
    }
    EXPECT_EQ(in[at[k] + sizes[k]], 0) << "the gap after the device of size " << sizes[k];
  }
  rt->finish();
}

// Issue 23: in virtual time with no hook set the runtime runs a scan as one
// function (Runtime::scan_plain) instead of scan_latch() and
// run_programs_and_publish(). It must do exactly what they do without
// hooks: the same cell run with a hook set that does nothing (and so takes
// the two halves) must give the same images, device bytes and states,
// program state, scan counts and state changes, at every tick. Two tasks,
// acyclic requests (deliver_answers), a device whose link goes down and
// comes back (latch_state's noted changes) and a task tripped by its
// program throwing.
TEST(ScanSemantics, PlainScanEqualsHookedScan) {
  const char* cell = R"(
image: {inputs: 64, outputs: 64, memory: 16}
tasks:
  - {name: a, period: 1ms, programs: [Loop, Poll]}
  - {name: b, period: 3ms, programs: [Bit, Throw]}
programs:
  - {name: Loop, type: LoopCounter}
  - {name: Poll, type: RecordPoller}
  - {name: Bit, type: BitWriter, bind: {mine: "%QX8.5"}}
  - {name: Throw, type: Thrower}
plugins: [{name: sim}]
devices:
  - {name: echo, plugin: sim, model: loopback, input: "%IB16", output: "%QB16", task: a,
     params: {size: 12}}
  - {name: plant, plugin: sim, model: first_order, input: "%IB32", output: "%QB32", task: b,
     params: {link_down_at: 40ms, link_down_for: 25ms}}
)";
  struct Noop final : ScanHooks {
    [[nodiscard]] bool whole_image() const override { return false; }
    void before_programs(TaskRuntime&, const ScanContext&) override { ++scans; }
    int scans = 0;
  } noop;
  auto plain = plctest::make_runtime(cell);
  auto hooked = plctest::make_runtime(cell);
  hooked->add_hooks(&noop);
  plain->start(io::ClockMode::Virtual);
  hooked->start(io::ClockMode::Virtual);
  const auto same_bytes = [](std::span<const std::uint8_t> x, std::span<const std::uint8_t> y) {
    return std::equal(x.begin(), x.end(), y.begin(), y.end());
  };
  for (int k = 0; k < 300; ++k) {
    if (k == 150) {
      // Task b's program throws: the task stops, its outputs safe.
      static_cast<plctest::Thrower*>(plain->program("Throw"))->fire = true;
      static_cast<plctest::Thrower*>(hooked->program("Throw"))->fire = true;
    }
    static_cast<plctest::BitWriter*>(plain->program("Bit"))->value = (k / 7) % 2 == 0;
    static_cast<plctest::BitWriter*>(hooked->program("Bit"))->value = (k / 7) % 2 == 0;
    plain->tick();
    hooked->tick();
    for (io::Area a : {io::Area::Input, io::Area::Output, io::Area::Memory})
      ASSERT_TRUE(same_bytes(plain->image().area(a), hooked->image().area(a)))
          << "global area " << int(a) << " at tick " << k;
    for (std::size_t i = 0; i < plain->tasks().size(); ++i) {
      const TaskRuntime& p = *plain->tasks()[i];
      const TaskRuntime& h = *hooked->tasks()[i];
      for (io::Area a : {io::Area::Input, io::Area::Output, io::Area::Memory})
        ASSERT_TRUE(same_bytes(p.image.area(a), h.image.area(a)))
            << "task " << p.name << " area " << int(a) << " at tick " << k;
      ASSERT_EQ(p.cycle, h.cycle) << p.name << " at tick " << k;
      ASSERT_EQ(p.stats.scans(), h.stats.scans()) << p.name << " at tick " << k;
      // One scan in kVirtualTimedEvery timed (the first of each), the same
      // ones (scan_plain's timed and untimed copies).
      constexpr std::uint64_t every = Runtime::kVirtualTimedEvery;
      ASSERT_EQ(p.stats.snapshot().scan_ns.count(), h.stats.snapshot().scan_ns.count())
          << p.name << " at tick " << k;
      ASSERT_EQ(p.stats.snapshot().scan_ns.count(), (p.stats.scans() + every - 1) / every)
          << p.name << " at tick " << k;
      ASSERT_EQ(p.scan_timed, h.scan_timed) << p.name << " at tick " << k;
      ASSERT_EQ(p.stopped.load(), h.stopped.load()) << p.name << " at tick " << k;
      ASSERT_EQ(p.scan_seq.load(), h.scan_seq.load()) << p.name << " at tick " << k;
      ASSERT_EQ(p.scan_started_ns.load(), -1);
      ASSERT_EQ(p.scan_time, h.scan_time) << p.name << " at tick " << k;
    }
    auto* ps = static_cast<io::SimPlugin*>(plain->plugin("sim"));
    auto* hs = static_cast<io::SimPlugin*>(hooked->plugin("sim"));
    for (const char* d : {"echo", "plant"}) {
      ASSERT_TRUE(same_bytes(ps->device(d)->outputs(), hs->device(d)->outputs())) << d << " " << k;
      ASSERT_TRUE(same_bytes(ps->device(d)->inputs(), hs->device(d)->inputs())) << d << " " << k;
      const auto pc = ps->device(d)->link().last_change();
      const auto hc = hs->device(d)->link().last_change();
      ASSERT_EQ(ps->device(d)->link().state(), hs->device(d)->link().state()) << d << " " << k;
      ASSERT_EQ(pc.count, hc.count) << d << " at tick " << k;
      ASSERT_EQ(pc.scan, hc.scan) << d << " at tick " << k;
      ASSERT_EQ(pc.time, hc.time) << d << " at tick " << k;
    }
    const auto* pl = static_cast<plctest::LoopCounter*>(plain->program("Loop"));
    const auto* hl = static_cast<plctest::LoopCounter*>(hooked->program("Loop"));
    ASSERT_EQ(pl->count, hl->count);
    ASSERT_EQ(pl->echoed, hl->echoed);
    ASSERT_EQ(pl->ctu.CV, hl->ctu.CV);
    const auto* pp = static_cast<plctest::RecordPoller*>(plain->program("Poll"));
    const auto* hp = static_cast<plctest::RecordPoller*>(hooked->program("Poll"));
    ASSERT_EQ(pp->answers, hp->answers) << "at tick " << k;
  }
  const auto* pp = static_cast<plctest::RecordPoller*>(plain->program("Poll"));
  EXPECT_GT(pp->answers, 50) << "the requests were answered";
  EXPECT_GT(plain->plugin("sim")->link(1).last_change().count, 1u) << "the link went and came";
  EXPECT_TRUE(plain->tasks()[1]->stopped.load()) << "the thrower stopped its task";
  EXPECT_FALSE(plain->tasks()[0]->stopped.load());
  EXPECT_EQ(noop.scans, 300 + 51) << "the hooked runtime took the halves";
  plain->finish();
  hooked->finish();
}

// A latch skips its devices' states while no link's state changed since its
// task's last latch (Runtime::state_changes_). Checked against the states
// latched at every latch: states set between the scans of one tick (task a's
// devices after b's scan; set at a tick's begin, the plugin's step sets them
// again), set twice, set to what they were, set back; the link cut.
TEST(ScanSemantics, LatchSkipsStatesOnlyWhenNoneChanged) {
  auto rt = plctest::make_runtime(R"(
image: {inputs: 64, outputs: 64, memory: 16}
tasks:
  - {name: b, period: 2ms, programs: [Bit]}
  - {name: a, period: 1ms, programs: [Loop]}
programs:
  - {name: Loop, type: LoopCounter}
  - {name: Bit, type: BitWriter, bind: {mine: "%QX8.5"}}
plugins: [{name: sim}]
devices:
  - {name: echo, plugin: sim, model: loopback, input: "%IB16", output: "%QB16", task: a,
     params: {size: 4}}
  - {name: quiet, plugin: sim, model: loopback, input: "%IB24", output: "%QB24", task: a,
     params: {size: 4}}
  - {name: plant, plugin: sim, model: first_order, input: "%IB32", output: "%QB32", task: b,
     params: {link_down_at: 40ms, link_down_for: 25ms}}
  - {name: other, plugin: sim, model: loopback, input: "%IB40", output: "%QB40", task: b,
     params: {size: 4}}
)");
  auto* sim = static_cast<io::SimPlugin*>(rt->plugin("sim"));
  struct Dev {
    const char* name;
    std::size_t task;
    io::DeviceState latched;
    std::uint64_t count = 0, scan = 0;
  };
  std::vector<Dev> devs = {{"echo", 1, {}}, {"quiet", 1, {}}, {"plant", 0, {}}, {"other", 0, {}}};
  for (Dev& d : devs) d.latched = sim->device(d.name)->link().state();
  rt->start(io::ClockMode::Virtual);
  std::uint32_t rng = 12345;
  const auto next = [&rng] { return rng = rng * 1664525u + 1013904223u, rng >> 8; };
  int unchanged = 0;
  for (int k = 0; k < 3000; ++k) {
    // Before a scan (after another task's scan of the same tick, or after
    // the plugin's step at a tick's begin): now and then a state set, once
    // or more, to anything (also what it was).
    for (int n = next() % 4; n > 0 && next() % 3 == 0; --n) {
      io::DeviceLink& link = sim->device(devs[next() % devs.size()].name)->link();
      link.set_state(static_cast<io::DeviceState>(next() % 3));
    }
    TaskRuntime* t = rt->step_scan();
    ASSERT_NE(t, nullptr);
    for (Dev& d : devs) {
      const io::DeviceLink& link = sim->device(d.name)->link();
      if (d.task == t->order) {
        // This scan latched: the state as it is now (no step since).
        const io::DeviceState live = link.live_state();
        if (live != d.latched) {
          d.latched = live;
          ++d.count;
          d.scan = t->cycle;
        } else {
          ++unchanged;
        }
      }
      ASSERT_EQ(link.state(), d.latched) << d.name << " after scan " << k;
      const auto c = link.last_change();
      ASSERT_EQ(c.count, d.count) << d.name << " after scan " << k;
      ASSERT_EQ(c.scan, d.scan) << d.name << " after scan " << k;
    }
  }
  EXPECT_GT(devs[0].count, 20u) << "set between b's scan and a's";
  EXPECT_GE(devs[2].count, 2u) << "cut and back";
  EXPECT_GT(unchanged, 100);
  rt->finish();
}

// SimDevice::step() takes its usual path without looking at the link cut
// while none is configured (link_down_at < 0): it relies on was_down_ being
// false then (set_link_down() with a negative time clears it). Over random
// reconfigurations of the cut (also mid-cut, also back to none and again)
// the model sees the outputs the full logic gives: the PLC's, or those at
// the start of the present cut.
TEST(ScanSemantics, SimDeviceUsualStepEqualsFullLinkCutLogic) {
  struct Probe final : io::DeviceModel {
    [[nodiscard]] std::size_t input_size() const override { return 2; }
    [[nodiscard]] std::size_t output_size() const override { return 2; }
    void step(TIME, TIME, std::span<const std::uint8_t> from_plc,
              std::span<std::uint8_t> to_plc) override {
      seen = {from_plc[0], from_plc[1]};
      to_plc[0] = static_cast<std::uint8_t>(++steps);
    }
    std::array<std::uint8_t, 2> seen{};
    std::uint32_t steps = 0;
  };
  auto owned = std::make_unique<Probe>();
  Probe& probe = *owned;
  io::SimDevice dev(std::move(owned));
  // The full logic, as SimDevice::step() had it before its usual path.
  TIME at{-1}, dur{0};
  bool was_down = false;
  std::array<std::uint8_t, 2> cut{};
  std::uint32_t rng = 987654321;
  const auto next = [&rng] { return rng = rng * 1664525u + 1013904223u, rng >> 8; };
  const TIME ms(std::chrono::milliseconds(1));
  int cuts = 0, fresh_cuts_after_none = 0;
  bool none_since_cut = false;
  for (int k = 0; k < 20000; ++k) {
    const TIME now = k * ms;
    if (next() % 8 == 0) {
      switch (next() % 4) {
        case 0:  // no cut
          at = TIME(-1);
          dur = TIME(0);
          break;
        case 1:  // a cut from now
          at = now;
          dur = TIME((1 + next() % 20) * ms);
          break;
        default:  // a cut somewhere around now
          at = TIME(std::int64_t(next() % 60) * ms + now - 30 * ms);
          if (at.count() < 0) at = TIME(0);
          dur = TIME((1 + next() % 40) * ms);
      }
      dev.set_link_down(at, dur);
    }
    dev.outputs()[0] = static_cast<std::uint8_t>(next());
    dev.outputs()[1] = static_cast<std::uint8_t>(next());
    const bool down = at.count() >= 0 && now >= at && now - at < dur;
    std::array<std::uint8_t, 2> expect{dev.outputs()[0], dev.outputs()[1]};
    if (down) {
      if (!was_down) {
        cut = expect;
        ++cuts;
        fresh_cuts_after_none += none_since_cut;
        none_since_cut = false;
      }
      was_down = true;
      expect = cut;
    } else {
      was_down = false;
    }
    if (at.count() < 0 && k > 0) none_since_cut = true;
    dev.step(now, ms);
    ASSERT_EQ(probe.seen, expect) << "step " << k;
    ASSERT_EQ(dev.link().state(), down ? io::DeviceState::Offline : io::DeviceState::Online)
        << "step " << k;
  }
  EXPECT_GT(cuts, 200);
  EXPECT_GT(fresh_cuts_after_none, 20);
}

// Runtime::any_task_alive() is a count that trip() and finish() keep
// (tasks_alive_): the virtual-time loop runs on while one task is left and
// ends at the tick after the last one stopped, as the loop over the tasks'
// stopped flags did; step_scan() finds no task then.
TEST(ScanSemantics, AliveCountFollowsTheStoppedTasks) {
  const char* cell = R"(
tasks:
  - {name: a, period: 1ms, programs: [A]}
  - {name: b, period: 2ms, programs: [B]}
programs:
  - {name: A, type: Thrower}
  - {name: B, type: Thrower}
)";
  {  // one of two stopped: the run goes on to its end
    auto rt = plctest::make_runtime(cell);
    static_cast<plctest::Thrower*>(rt->program("A"))->fire = true;
    rt->run(io::ClockMode::Virtual, std::chrono::milliseconds(10));
    EXPECT_TRUE(rt->tasks()[0]->stopped.load());
    EXPECT_EQ(rt->now(), std::chrono::milliseconds(10));
  }
  {  // both stopped in the first tick: the run ends after it
    auto rt = plctest::make_runtime(cell);
    static_cast<plctest::Thrower*>(rt->program("A"))->fire = true;
    static_cast<plctest::Thrower*>(rt->program("B"))->fire = true;
    rt->run(io::ClockMode::Virtual, std::chrono::milliseconds(10));
    EXPECT_EQ(rt->now(), std::chrono::milliseconds(1));
  }
  {  // step by step: b stops at 2 ms, a at 3 ms; then no scan is left
    auto rt = plctest::make_runtime(cell);
    rt->start(io::ClockMode::Virtual);
    auto* a = static_cast<plctest::Thrower*>(rt->program("A"));
    auto* b = static_cast<plctest::Thrower*>(rt->program("B"));
    for (int i = 0; i < 3; ++i) ASSERT_NE(rt->step_scan(), nullptr);  // a 0, b 0, a 1 ms
    b->fire = true;
    EXPECT_EQ(rt->step_scan(), rt->tasks()[0].get());  // a at 2 ms
    EXPECT_EQ(rt->step_scan(), rt->tasks()[1].get());  // b at 2 ms: stops
    EXPECT_TRUE(rt->tasks()[1]->stopped.load());
    a->fire = true;
    EXPECT_EQ(rt->step_scan(), rt->tasks()[0].get());  // a at 3 ms: stops
    EXPECT_EQ(rt->step_scan(), nullptr) << "every task stopped";
    rt->finish();
  }
}

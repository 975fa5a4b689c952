// Two virtual-time runs of the same config give identical trace files
// (issue 2 acceptance), through plcrun and in-process.
#include <gtest/gtest.h>

#include "plc/debug/trace.hpp"
#include "test_helpers.hpp"

namespace {

std::string demo_config() { return plctest::source_path("programs/demo/cell.yaml"); }

}  // namespace

TEST(Determinism, TwoPlcrunRunsOfTheDemoGiveIdenticalTraces) {
  const std::string vars =
      "Tank.level,Tank.valve,Tank.step,Tank.hold.ET,Tank.batches.CV,Tank.tank_status,Supervisor."
      "enable";
  std::string traces[2];
  for (int i = 0; i < 2; ++i) {
    const std::string file = plctest::temp_path("det" + std::to_string(i) + ".csv");
    const auto r =
        plctest::run_command(plctest::plcrun_path() + " " + demo_config() +
                             " --virtual --for 30s -q --trace " + file + " --trace-vars " + vars);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    traces[i] = plctest::read_file(file);
  }
  ASSERT_GT(traces[0].size(), 30000u * 10) << "one row per 1 ms scan";
  EXPECT_EQ(traces[0], traces[1]);
  // The trace is not trivially constant: the tank really cycles.
  EXPECT_NE(traces[0].find(",3,"), std::string::npos) << "reached the Drain step";
}

TEST(Determinism, InProcessRunsMatchAndDevicesStepInLockstep) {
  const char* cell = R"(
tasks: [{name: main, period: 1ms, programs: [Loop]}]
programs: [{name: Loop, type: LoopCounter}]
plugins: [{name: sim}]
devices: [{name: echo, plugin: sim, model: loopback, input: "%IB0", output: "%QB0", params: {size: 4}}]
)";
  std::string out[2];
  for (int i = 0; i < 2; ++i) {
    auto rt = plctest::make_runtime(cell);
    const std::string file = plctest::temp_path("inproc" + std::to_string(i) + ".csv");
    {
      plc::debug::Trace trace(rt->vars(), rt->image(), rt->byte_order());
      for (const char* v : {"Loop.count", "Loop.echoed", "Loop.t.ET", "Loop.ctu.CV"})
        ASSERT_EQ(trace.add(v), "");
      ASSERT_EQ(trace.start(file), "");
      rt->add_scan_observer(
          [&](const plc::TaskRuntime&, const plc::ScanContext& ctx) { trace.sample(ctx); });
      rt->run(plc::io::ClockMode::Virtual, std::chrono::seconds(2));
      trace.stop();
    }
    out[i] = plctest::read_file(file);
  }
  EXPECT_EQ(out[0], out[1]);
  // Lockstep: what the program wrote in scan k is back in its inputs in
  // scan k+1 (one device step of delay), every time.
  EXPECT_NE(out[0].find("\n1000000,1,2,1,"), std::string::npos) << out[0].substr(0, 200);
  EXPECT_NE(out[0].find("\n1999000000,1999,2000,1999,"), std::string::npos);
}

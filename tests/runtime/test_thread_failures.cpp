// Issue 21 follow-up, point 1: no uncaught exception ends plcrun, in any
// thread (plc/thread_guard.hpp). A device model that throws in the sim
// plugin's real-time thread, or in its step() in virtual time (the scan
// thread's), fails the plugin: the message "<program>: <thread>: <what>",
// its devices at Fault so the program sees them gone and puts its outputs
// to the safe value, the cell scanning on, plcrun's exit code 1. An
// observer that throws stops its task like a program exception does.
#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "cli.hpp"
#include "plc/io/device_model.hpp"
#include "plc/io/device_port.hpp"
#include "plc/io/located.hpp"
#include "plc/program.hpp"
#include "plc/thread_guard.hpp"
#include "test_helpers.hpp"

namespace {

using namespace plc;

// Counts up in its input word until `at` (param, default 50 ms), then
// throws from step(): a model with a bug.
class ExplodingModel : public io::DeviceModel {
 public:
  explicit ExplodingModel(const io::ModelParams& p)
      : at_(p.get_time("at", std::chrono::milliseconds(50), TIME(0), std::chrono::hours(1))) {
    p.reject_unknown();
  }
  [[nodiscard]] std::size_t input_size() const override { return 2; }
  [[nodiscard]] std::size_t output_size() const override { return 2; }
  void step(TIME now, TIME, std::span<const std::uint8_t>, std::span<std::uint8_t> in) override {
    if (now >= at_) throw std::runtime_error("model exploded");
    in[0] = static_cast<std::uint8_t>(++count_);
  }

 private:
  TIME at_;
  std::uint8_t count_ = 0;
};
PLC_REGISTER_DEVICE_MODEL("test_exploding", ExplodingModel)

// Drives %QW4 to 1234 while its device is online, to 0 (its safe value)
// when it is not, as an FB does for a device that is gone.
class DeviceWatcher : public ProgramBase<DeviceWatcher> {
 public:
  io::DevicePort dev{"boom"};
  io::Located<INT> out{"%QW4"};
  DINT scans = 0;
  DINT offline_scans = 0;
  void cycle(const ScanContext&) override {
    ++scans;
    out = dev.online() ? INT(1234) : INT(0);
    if (!dev.online()) ++offline_scans;
  }
  PLC_REFLECT(dev, out, scans, offline_scans)
};
PLC_REGISTER_PROGRAM(DeviceWatcher)

const char* kCell = R"(
cell: boom
tasks: [{name: main, period: 1ms, programs: [Watch]}]
programs: [{name: Watch, type: DeviceWatcher}]
plugins: [{name: sim, params: {step: 1ms}}]
devices:
  - {name: boom, plugin: sim, model: test_exploding, input: "%IB0", output: "%QB0"}
)";

INT out_word(Runtime& rt) {
  return INT(std::stoi(VarRegistry::format(*rt.vars().find("Watch.out"))));
}

void expect_plugin_failed(Runtime& rt, const std::string& err, const char* thread) {
  io::Plugin& p = *rt.devices()[0].plugin;
  EXPECT_TRUE(p.failed());
  EXPECT_NE(p.failure().find("model exploded"), std::string::npos) << p.failure();
  EXPECT_EQ(p.link(0).live_state(), io::DeviceState::Fault);
  EXPECT_NE(err.find(std::string(": ") + thread + ": model exploded\n"), std::string::npos) << err;
  // The cell scanned on and the program saw the device gone: safe output.
  auto* w = static_cast<DeviceWatcher*>(rt.program("Watch"));
  EXPECT_GT(w->offline_scans, 10) << "the task did not scan on after the failure";
  EXPECT_EQ(out_word(rt), 0);
  EXPECT_EQ(rt.tasks()[0]->stats.snapshot().stop_reason, "");
}

TEST(ThreadFailures, ModelThrowingInVirtualTimeFailsItsPluginAndTheCellScansOn) {
  auto rt = plctest::make_runtime(kCell);
  const auto failures = thread_failures();
  testing::internal::CaptureStderr();
  rt->run(io::ClockMode::Virtual, std::chrono::milliseconds(200));
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(thread_failures(), failures + 1);
  expect_plugin_failed(*rt, err, "plugin 'sim'");
  EXPECT_EQ(static_cast<DeviceWatcher*>(rt->program("Watch"))->scans, 200);
}

TEST(ThreadFailures, ModelThrowingInTheSimThreadInRealTimeFailsItsPlugin) {
  auto rt = plctest::make_runtime(kCell);
  const auto failures = thread_failures();
  testing::internal::CaptureStderr();
  // The model throws 50 ms into the run; the run ends at 400 ms.
  rt->run(io::ClockMode::RealTime, std::chrono::milliseconds(400));
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(thread_failures(), failures + 1);
  expect_plugin_failed(*rt, err, "sim plugin");
}

// An observer (trace, status line, HMI snapshot) that throws in the scan
// thread: the task stops with its outputs safe, as for a program exception.
void observer_throws(io::ClockMode mode) {
  auto rt = plctest::make_runtime(R"(
tasks: [{name: main, period: 1ms, programs: [Watch]}]
programs: [{name: Watch, type: DeviceWatcher}]
plugins: [{name: sim, params: {step: 1ms}}]
devices:
  - {name: boom, plugin: sim, model: test_exploding, input: "%IB0", output: "%QB0", params: {at: 1h}}
)");
  rt->add_scan_observer([](const TaskRuntime&, const ScanContext& ctx) {
    if (ctx.cycle == 20) throw std::runtime_error("observer broke");
  });
  testing::internal::CaptureStderr();
  rt->run(mode, std::chrono::milliseconds(200));
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find(": task 'main': observer broke\n"), std::string::npos) << err;
  EXPECT_NE(rt->tasks()[0]->stats.snapshot().stop_reason.find("scan failed: observer broke"),
            std::string::npos);
  EXPECT_TRUE(rt->tasks()[0]->stopped.load());
}

TEST(ThreadFailures, ObserverThrowingStopsItsTaskSafelyInVirtualTime) {
  observer_throws(io::ClockMode::Virtual);
}
TEST(ThreadFailures, ObserverThrowingStopsItsTaskSafelyInRealTime) {
  observer_throws(io::ClockMode::RealTime);
}

// plcrun as a whole: the failure is said, the summary names it, exit code 1.
void plcrun_exit_code(const char* mode) {
  const std::string cfg = plctest::write_temp(std::string("boom_") + mode + ".yaml", kCell);
  std::vector<std::string> args = {"plcrun", cfg,  mode,           "--for",
                                   "300ms",  "-q", "--print-vars", "Watch.out"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  const int rc = plcrun_main(static_cast<int>(argv.size()), argv.data());
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(rc, 1) << out << err;
  EXPECT_NE(err.find("model exploded"), std::string::npos) << err;
  EXPECT_NE(out.find("device boom       (sim): FAILED ("), std::string::npos) << out;
  EXPECT_NE(out.find("Watch.out = 0\n"), std::string::npos) << out;
}

TEST(ThreadFailures, PlcrunExitsWithOneAfterAPluginThreadFailedInVirtualTime) {
  plcrun_exit_code("--virtual");
}
TEST(ThreadFailures, PlcrunExitsWithOneAfterAPluginThreadFailedInRealTime) {
  plcrun_exit_code("--realtime");
}

}  // namespace

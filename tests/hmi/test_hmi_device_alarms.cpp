// Device health on the HMI bridge (issue 13: "device diagnostics and
// alarms"), over memq:// in virtual time: a sim device whose model stops
// answering goes Offline on PREFIX_DIAG and a "lost" alarm arrives on
// PREFIX_ALARM with the scan that first saw it; answering again gives Online
// and a "back" alarm.
#include <gtest/gtest.h>

#include <atomic>

#include "hmi_test_cell.hpp"
#include "plc/io/device_model.hpp"
#include "plc/io/sim_plugin.hpp"
#include "softplc_hmi/alarm_t.hpp"
#include "softplc_hmi/diagnostics_t.hpp"

using namespace plc;

namespace {

// A loopback whose answering the test switches (DeviceModel::answering: the
// sim plugin then reports the device Offline and keeps its last inputs).
class SwitchedLoopback final : public io::DeviceModel {
 public:
  explicit SwitchedLoopback(const io::ModelParams& p) { p.reject_unknown(); }
  std::size_t input_size() const override { return 2; }
  std::size_t output_size() const override { return 2; }
  void step(TIME, TIME, std::span<const std::uint8_t> from_plc,
            std::span<std::uint8_t> to_plc) override {
    std::copy(from_plc.begin(), from_plc.end(), to_plc.begin());
  }
  void set_answering(bool on) { set_answering_now(on); }
};
PLC_REGISTER_DEVICE_MODEL("hmi_test_switched", SwitchedLoopback)

// The demo cell with a second device, exchanged by the 10 ms task.
std::string cell_with_probe() {
  std::string cell = plctest::demo_yaml();
  const auto at = cell.find("\nsafe_values:");
  EXPECT_NE(at, std::string::npos);
  cell.insert(at, R"(
  - name: probe
    plugin: sim
    model: hmi_test_switched
    input: "%IB100"
    output: "%QB100"
    task: slow
)");
  return cell;
}

struct Seen {
  std::vector<softplc_hmi::alarm_t> alarms;
  std::vector<softplc_hmi::diagnostics_t> diags;
  void on(const softplc_hmi::alarm_t& a) { alarms.push_back(a); }
  void on(const softplc_hmi::diagnostics_t& d) { diags.push_back(d); }
};

const softplc_hmi::device_t* device(const softplc_hmi::diagnostics_t& d, const std::string& n) {
  for (const auto& dv : d.devices)
    if (dv.name == n) return &dv;
  return nullptr;
}

// One bridge round, then what it published handed to the test's
// subscriptions (memq:// delivers on the next handle of the same transport).
void round(plctest::HmiCell& h) {
  h.bridge->service();
  for (int i = 0; i < 100 && h.bridge->transport().handle_timeout(0) > 0; ++i) {
  }
}

std::uint64_t slow_scans(debug::Debugger& dbg) {
  return dbg.runtime().tasks()[1]->stats.snapshot().scans;
}

}  // namespace

TEST(HmiBridge, DeviceLostAndBackAlarms) {
  plctest::HmiCell h(plctest::kHmiSection, "", cell_with_probe());
  Seen seen;
  plc::hmi::subscribe_checked<softplc_hmi::alarm_t>(h.bridge->transport(),
                                                    h.bridge->channels().alarm, &seen);
  plc::hmi::subscribe_checked<softplc_hmi::diagnostics_t>(h.bridge->transport(),
                                                          h.bridge->channels().diag, &seen);
  auto* sim = static_cast<io::SimPlugin*>(h.dbg->runtime().plugin("sim"));
  auto& model = static_cast<SwitchedLoopback&>(sim->device("probe")->model());
  ASSERT_EQ(h.dbg->runtime().tasks()[1]->name, "slow");
  // Publishes the diagnostics and hands over what the bridge sent.
  auto diagnostics = [&] {
    seen.diags.clear();
    h.bridge->publish_diagnostics();
    round(h);
    EXPECT_EQ(seen.diags.size(), 1U);
    return seen.diags.empty() ? softplc_hmi::diagnostics_t{} : seen.diags.back();
  };

  ASSERT_TRUE(h.dbg->step(20).ok);
  round(h);
  EXPECT_TRUE(seen.alarms.empty()) << seen.alarms.front().text;
  auto d = diagnostics();
  ASSERT_NE(device(d, "probe"), nullptr);
  EXPECT_EQ(device(d, "probe")->state, "online");
  EXPECT_EQ(device(d, "probe")->diagnostics, "online");  // the sim plugin's text
  EXPECT_EQ(device(d, "probe")->task, "slow");
  EXPECT_EQ(device(d, "tank1")->state, "online");
  EXPECT_EQ(d.n_alarms, 0);

  // Lost: the next scan of the slow task is the first to see it.
  model.set_answering(false);
  const std::uint64_t before = slow_scans(*h.dbg);
  ASSERT_TRUE(h.dbg->step(1, "slow").ok);
  round(h);
  ASSERT_EQ(seen.alarms.size(), 1U);
  const auto lost = seen.alarms.front();
  EXPECT_EQ(lost.kind, "device_lost");
  EXPECT_EQ(lost.source, "device probe");
  EXPECT_TRUE(lost.active);
  EXPECT_EQ(lost.from_state, "online");
  EXPECT_EQ(lost.to_state, "offline");
  EXPECT_EQ(lost.task, "slow");
  EXPECT_EQ(lost.scan, std::int64_t(before + 1)) << lost.text;
  EXPECT_EQ(lost.plc_time_ns, h.dbg->runtime().tasks()[1]->scan_time.count());
  d = diagnostics();
  EXPECT_EQ(device(d, "probe")->state, "offline");
  EXPECT_EQ(device(d, "probe")->diagnostics, "offline");
  EXPECT_EQ(device(d, "probe")->changes, 1);
  EXPECT_EQ(device(d, "tank1")->state, "online");
  ASSERT_EQ(d.n_alarms, 1);
  EXPECT_EQ(d.alarms[0].source, "device probe");
  EXPECT_EQ(d.alarms[0].scan, lost.scan);

  // Still lost: no new alarm, however many scans.
  ASSERT_TRUE(h.dbg->step(30).ok);
  round(h);
  EXPECT_EQ(seen.alarms.size(), 1U);

  // Back.
  model.set_answering(true);
  const std::uint64_t again = slow_scans(*h.dbg);
  ASSERT_TRUE(h.dbg->step(1, "slow").ok);
  round(h);
  ASSERT_EQ(seen.alarms.size(), 2U);
  const auto back = seen.alarms.back();
  EXPECT_EQ(back.kind, "device_back");
  EXPECT_FALSE(back.active);
  EXPECT_EQ(back.from_state, "offline");
  EXPECT_EQ(back.to_state, "online");
  EXPECT_EQ(back.scan, std::int64_t(again + 1)) << back.text;
  d = diagnostics();
  EXPECT_EQ(device(d, "probe")->state, "online");
  EXPECT_EQ(device(d, "probe")->changes, 2);
  EXPECT_EQ(d.n_alarms, 0);
}

// A flap shorter than one bridge round (lost and back between two rounds)
// is not missed: the link counts every change its task's scans saw.
TEST(HmiBridge, DeviceFlapBetweenTwoBridgeRoundsIsReported) {
  plctest::HmiCell h(plctest::kHmiSection, "", cell_with_probe());
  Seen seen;
  plc::hmi::subscribe_checked<softplc_hmi::alarm_t>(h.bridge->transport(),
                                                    h.bridge->channels().alarm, &seen);
  auto* sim = static_cast<io::SimPlugin*>(h.dbg->runtime().plugin("sim"));
  auto& model = static_cast<SwitchedLoopback&>(sim->device("probe")->model());
  ASSERT_TRUE(h.dbg->step(5).ok);
  round(h);
  model.set_answering(false);
  ASSERT_TRUE(h.dbg->step(1, "slow").ok);
  model.set_answering(true);
  const std::uint64_t back_scan = slow_scans(*h.dbg) + 1;
  ASSERT_TRUE(h.dbg->step(1, "slow").ok);
  round(h);  // one round after both changes
  ASSERT_EQ(seen.alarms.size(), 2U);
  EXPECT_EQ(seen.alarms[0].kind, "device_lost");
  EXPECT_EQ(seen.alarms[0].scan, 0) << "its scan is not kept: " << seen.alarms[0].text;
  EXPECT_EQ(seen.alarms[1].kind, "device_back");
  EXPECT_EQ(seen.alarms[1].scan, std::int64_t(back_scan));
}

// A warm start that fell back to a cold one (every copy of the retain file
// damaged, issue 21) is an active alarm in every diagnostics_t for the whole
// run: plcrun notes it at start-up (add_start_alarm), next to the stopped
// tasks and the devices not online.
// The alarm crosses from plcrun's host to the bridge in the cell layout.
TEST(HmiBridge, RetainColdStartFallbackIsAnActiveAlarm) {
  plctest::HmiCell h(plctest::kHmiSection, "", plctest::demo_yaml(), [](plc::hmi::Host& host) {
    host.add_start_alarm("retain_cold_start", "retain",
                         "cold start INSTEAD OF A WARM START: no valid copy");
  });
  Seen seen;
  plc::hmi::subscribe_checked<softplc_hmi::diagnostics_t>(h.bridge->transport(),
                                                          h.bridge->channels().diag, &seen);
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(h.dbg->step(5).ok);
    h.bridge->publish_diagnostics();
    round(h);
    ASSERT_EQ(seen.diags.size(), std::size_t(i + 1));
    const auto& d = seen.diags.back();
    ASSERT_EQ(d.n_alarms, 1);
    EXPECT_EQ(d.alarms[0].kind, "retain_cold_start");
    EXPECT_EQ(d.alarms[0].source, "retain");
    EXPECT_TRUE(d.alarms[0].active);
    EXPECT_EQ(d.alarms[0].text, "cold start INSTEAD OF A WARM START: no valid copy");
  }
}

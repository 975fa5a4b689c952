// lcm-spy shows our types field by field (issue 22: Debian's lcm-spy
// wrapper passes -Xincgc, which JDK 17 refuses, and the types' jar was not
// built by default). A session of the demo cell's bridge (memq://, virtual
// time) is written in lcm-logger's format; lcm-spy's own window (lcm.spy.Spy)
// replays it (LCM's file:// provider) under Xvfb with build/lib/softplc_hmi.jar
// on its class path, as build/bin/plc-lcm-spy runs it, and what Spy decoded
// must be what the bridge sent: every value of the last values_t, the
// variables of the description. Skipped when the jar or xvfb-run is missing
// (scripts/setup installs both); every wait is bounded.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include "hmi_test_cell.hpp"
#include "runtime/test_helpers.hpp"
#include "softplc_hmi/cell_description_t.hpp"
#include "softplc_hmi/values_t.hpp"

namespace {

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The bridge's messages, as lcm-logger would write them; values_t up to
// the first full one (every published variable of its task), so that the
// last one Spy receives is that one.
struct Recorder {
  lcm::LogFile* log = nullptr;
  std::int64_t n = 0;
  bool full_seen = false;
  softplc_hmi::values_t last_values;
  softplc_hmi::cell_description_t last_desc;
  void on(const plc::hmi::ReceiveBuffer& rb, const std::string& channel) {
    if (channel == "PLC_VALUES" && full_seen) return;
    lcm::LogEvent e{};
    e.eventnum = n++;
    e.timestamp = rb.recv_utime;
    e.channel = channel;
    e.datalen = std::int32_t(rb.data_size);
    e.data = const_cast<void*>(rb.data);
    log->writeEvent(&e);
    if (channel == "PLC_VALUES") {
      EXPECT_TRUE(plc::hmi::checked_decode(rb.data, rb.data_size, last_values));
      full_seen = last_values.full;
    }
    if (channel == "PLC_DESC") {
      EXPECT_TRUE(plc::hmi::checked_decode(rb.data, rb.data_size, last_desc));
    }
  }
};

}  // namespace

TEST(HmiLcmSpy, SpyShowsOurTypesWithTheirValues) {
  if (std::string(PLC_SPY_CHECK_DIR).empty())
    GTEST_SKIP() << "build/lib/softplc_hmi.jar is not built (scripts/setup installs a JDK, "
                    "liblcm-java and libjchart2d-java)";
  if (plctest::run_command("command -v xvfb-run").exit_code != 0)
    GTEST_SKIP() << "xvfb-run is not installed (scripts/setup installs xvfb)";
  const std::string dir = ::testing::TempDir() + "hmi_spy_" + std::to_string(::getpid());
  ASSERT_EQ(plctest::run_command("rm -rf " + dir + " && mkdir -p " + dir).exit_code, 0);
  const std::string log_path = dir + "/session.lcm";
  Recorder rec;
  {
    lcm::LogFile log(log_path, "w");
    ASSERT_TRUE(log.good());
    rec.log = &log;
    plctest::HmiCell h;
    auto* s = h.bridge->transport().subscribe(
        "PLC_.*", [&rec](const plc::hmi::ReceiveBuffer& rb, const std::string& channel) {
          rec.on(rb, channel);
        });
    h.bridge->publish_description();
    for (int i = 0; i < 60; ++i) {
      h.dbg->step(1);
      h.bridge->service();
    }
    h.bridge->publish_stats();
    h.bridge->service();
    h.bridge->transport().unsubscribe(s);
  }
  ASSERT_TRUE(rec.full_seen);
  ASSERT_GT(rec.last_values.n, 3);
  ASSERT_GT(rec.last_desc.n, 10);

  // The wrapper starts the JVM (Debian's does not: -Xincgc).
  const auto help =
      plctest::run_command("timeout 60 " + plctest::bin_dir() + "/plc-lcm-spy --help");
  EXPECT_TRUE(has(help.output, "usage: lcm-spy")) << help.output;
  EXPECT_FALSE(has(help.output, "Unrecognized VM option")) << help.output;

  const std::string png = dir + "/spy.png";
  const std::string cp = std::string(PLC_LCM_JAR) + ":" + PLC_JCHART2D_JAR + ":" + PLC_HMI_JAR +
                         ":" + PLC_SPY_CHECK_DIR;
  const auto r = plctest::run_command(
      "timeout 120 xvfb-run -a -s '-screen 0 1280x800x24' " + std::string(PLC_JAVA) +
      " -Djava.net.preferIPv4Stack=true -cp " + cp + " SpyCheck 'file://" + log_path +
      "?speed=1' " + png + " PLC_VALUES PLC_DESC PLC_STATS");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "channel PLC_VALUES type softplc_hmi.values_t")) << r.output;
  EXPECT_TRUE(has(r.output, "channel PLC_DESC type softplc_hmi.cell_description_t")) << r.output;
  EXPECT_TRUE(has(r.output, "channel PLC_STATS type softplc_hmi.stats_t")) << r.output;
  // Values, not indices: the IEC text of each value of the last message.
  for (const auto& v : rec.last_values.values)
    EXPECT_TRUE(has(r.output, "value " + std::to_string(v.index) + " " + v.text + "\n"))
        << v.index << " " << v.text << "\n"
        << r.output;
  for (const auto& v : rec.last_desc.vars)
    EXPECT_TRUE(has(r.output, "var " + v.path + " " + v.type + "\n")) << v.path << "\n" << r.output;
  EXPECT_GT(plctest::read_file(png).size(), 1000U);
}

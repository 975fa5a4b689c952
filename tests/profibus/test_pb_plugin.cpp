// The `profibus` plugin's configuration (docs/config.md): errors point at
// the config line and column (plcrun exits 2), GSD errors keep the GSD's
// own file:line; the bus parameters follow the baud rate and the GSD.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>

#include "plc/io/record_request.hpp"
#include "plc/profibus/dp/services.hpp"
#include "plc/profibus/profibus_plugin.hpp"
#include "runtime/test_helpers.hpp"

namespace {

std::string cell(const std::string& plugin, const std::string& device) {
  return "cell: t\nclock: virtual\nimage: {inputs: 64, outputs: 64, memory: 8}\n"
         "tasks:\n  - name: main\n    period: 1ms\n    programs: []\n"
         "plugins:\n  - name: dp\n    type: profibus\n    params:\n" +
         plugin +
         "devices:\n  - name: scale\n    plugin: dp\n    model: pr5510\n    input: \"%IB0\"\n"
         "    output: \"%QB0\"\n    params:\n" +
         device;
}

std::string gsd() { return plctest::source_path("iec-io/profibus/gsd/GWT_5610.gsd"); }

plctest::RunResult run(const std::string& yaml) {
  const std::string f = plctest::write_temp("pb_plugin.yaml", yaml);
  // 50 ms: the start-up takes one message cycle per bus cycle (5 ms).
  return plctest::run_command(plctest::plcrun_path() + " " + f + " --for 50ms -q");
}

const std::string kGood = "      simulate: true\n";
std::string good_device() {
  return "      address: 5\n      gsd: " + gsd() + "\n      modules: \"8 Byte I/O Konsistent\"\n";
}

}  // namespace

TEST(PbPlugin, ErrorsPointAtTheConfigLine) {
  struct Case {
    std::string plugin, device, expect;
  };
  const Case cases[] = {
      {"      simulate: true\n      baud: 115200\n", good_device(),
       "pb_plugin.yaml:13:7: plugin 'dp': key 'baud': baud must be one of 9600"},
      {"      baud: 1500000\n", good_device(),
       "the profibus plugin needs transport: serial:DEVICE"},
      {"      transport: tcp:1\n", good_device(), "key 'transport'"},
      {kGood, "      gsd: " + gsd() + "\n      modules: \"8 Byte I/O Konsistent\"\n",
       "every PROFIBUS device needs its address"},
      {kGood,
       "      address: 1\n      gsd: " + gsd() + "\n      modules: \"8 Byte I/O Konsistent\"\n",
       "the device has the master's address"},
      {kGood, "      address: 5\n      gsd: " + gsd() + "\n      modules: \"32 Byte I/O\"\n",
       "no module '32 Byte I/O' in"},
      {kGood,
       "      address: 5\n      gsd: " + gsd() +
           "\n      modules: \"16 Byte I/O Konsistent\"\n      extra: 1\n",
       "device 'scale': unknown parameter 'extra'"},
      {kGood,
       "      address: 5\n      gsd: " +
           plctest::source_path("tests/profibus/data/GWT_5610_seed.gsd") +
           "\n      modules: \"8 Byte I/O Konsistent\"\n",
       "GWT_5610_seed.gsd:26: 'Baudraten' is not 'Keyword = Value'"},
      {kGood,
       "      address: 5\n      gsd: " + gsd() +
           "\n      modules: \"8 Byte I/O Konsistent; 8 Byte I/O Konsistent; 8 Byte I/O "
           "Konsistent; 8 Byte I/O Konsistent; 8 Byte I/O Konsistent\"\n",
       "5 modules, the GSD's Max_Module is 4"},
      {"      simulate: true\n      baud: 45450\n", good_device(), "does not list 45.45_supp = 1"},
  };
  for (const Case& c : cases) {
    const auto r = run(cell(c.plugin, c.device));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.expect << "\n" << r.output;
  }
}

// Bigger windows: 2 modules of 8 bytes for a 16-byte slave (the PR5510's
// 8-byte window in front, the rest zero), bus parameters at 12 Mbit/s from
// the GSD's MaxTsdr_12M.
TEST(PbPlugin, SixteenBytesAt12MbitWithTheGsdTiming) {
  const auto r = run(cell("      simulate: true\n      baud: 12000000\n",
                          "      address: 5\n      gsd: " + gsd() +
                              "\n      modules: \"8 Byte I/O Konsistent; 4 Word I/O Seperate\"\n"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("12000000 bit/s: TSL 1000, minTSDR 11, maxTSDR 800"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("max_retry 4"), std::string::npos);
  EXPECT_NE(r.output.find("scale (address 5): data exchange"), std::string::npos) << r.output;
}

// A relative gsd: is taken from the config file's folder (docs/config.md,
// "Relative paths"), whatever the current directory.
TEST(PbPlugin, RelativeGsdPathIsFromTheConfigFilesFolder) {
  const std::string copy = plctest::temp_path("pb_rel.gsd");
  plctest::write_temp("pb_rel.gsd", plctest::read_file(gsd()));
  const std::string bare = copy.substr(copy.rfind('/') + 1);
  const auto r = run(cell(kGood, "      address: 5\n      gsd: " + bare +
                                     "\n      modules: \"8 Byte I/O Konsistent\"\n"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("scale (address 5): data exchange"), std::string::npos) << r.output;
}

// active: false (docs/config.md): the device is configured but never
// called; the plugin says so at the start and the device never reaches data
// exchange.
TEST(PbPlugin, InactiveDeviceIsDeactivatedNotCalled) {
  const auto r = run(cell(kGood, good_device() + "      active: false\n"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("scale (address 5): deactivated (active: false)"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("data exchange"), std::string::npos) << r.output;
}

// The device path of transport: pty:PATH is a file the config names: a
// relative one is made in the config file's folder.
TEST(PbPlugin, RelativePtyPathIsInTheConfigFilesFolder) {
  const std::string line = plctest::temp_path("pb_rel_line");
  const std::string bare = line.substr(line.rfind('/') + 1);
  // In real time: no task watchdog, a stalled machine must not stop the run.
  std::string yaml = cell("      transport: \"pty:" + bare + "\"\n", good_device());
  yaml.replace(yaml.find("    period: 1ms\n"), 16, "    period: 1ms\n    watchdog: 0\n");
  const std::string f = plctest::write_temp("pb_rel_pty.yaml", yaml);
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + f + " --realtime --for 20ms");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("master 1 on pty " + line + " -> /dev/pts/"), std::string::npos)
      << r.output;
}

// dpslavesim's config (docs/config.md, dpslavesim): the pty it makes, the
// GSD and the capture are taken from the config file's folder, not from
// the current directory (here /).
TEST(PbSlaveSim, RelativePathsAreFromTheConfigFilesFolder) {
  const std::string dir = plctest::temp_path("pb_sim_dir");
  ASSERT_TRUE(::mkdir(dir.c_str(), 0755) == 0 || errno == EEXIST);
  {
    std::ofstream(dir + "/scale.gsd") << plctest::read_file(gsd());
    std::ofstream(dir + "/s.yaml") << "transport: \"pty:line\"\ncapture: cap.txt\nslaves:\n"
                                      "  - name: scale\n    model: pr5510\n"
                                      "    params: {bus: profibus}\n    address: 5\n"
                                      "    gsd: scale.gsd\n    io_bytes: 8\n";
  }
  const auto r = plctest::run_command("cd / && " + plctest::bin_dir() + "/dpslavesim " + dir +
                                      "/s.yaml --for 20ms");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("1 slave(s) on pty " + dir + "/line -> /dev/pts/"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("scale: address 5 Wait_Prm"), std::string::npos) << r.output;
  EXPECT_EQ(::access((dir + "/cap.txt").c_str(), F_OK), 0) << "the capture in the config's folder";
}

// Global_Control for FBs (docs/config.md): a record write of index 0xF000
// with Control_Command and Group_Select on any of the plugin's devices goes
// out at the end of the next bus cycle; the slave of that group freezes and
// syncs, and the master's diagnosis shows it. Any other record is refused
// (DP-V0 has none). The plugin in-process, simulated, in virtual time.
TEST(PbPlugin, GlobalControlRecordF000ReachesTheGroupOtherRecordsAreRefused) {
  plc::profibus::ProfibusPlugin plug;
  plc::io::ModelParams p;
  p.set("simulate", "true");
  p.set("log", "false");
  plug.configure(p);
  plc::io::DeviceSpec spec{"scale", "pr5510", {}};
  spec.params.set("address", "5");
  spec.params.set("gsd", gsd());
  spec.params.set("modules", "8 Byte I/O Konsistent");
  spec.params.set("group", "1");
  spec.params.set("freeze", "true");
  spec.params.set("sync", "true");
  plug.add_device(spec);
  plug.start(plc::io::ClockMode::Virtual);
  using namespace std::chrono_literals;
  plc::TIME now{0};
  auto run = [&](plc::TIME t) {
    for (plc::TIME end = now + t; now < end;) plug.step(now += 1ms, 1ms);
  };
  run(100ms);
  ASSERT_EQ(plug.master().state(0), plc::profibus::master::SlaveState::Online)
      << plug.diagnostics(0);
  namespace dp = plc::profibus::dp;
  const std::uint8_t gc[2] = {dp::kGcFreeze | dp::kGcSync, 0x01};
  plc::io::RecordRequest r;
  ASSERT_TRUE(r.prepare_write(plc::profibus::kGlobalControlRecord, gc));
  ASSERT_TRUE(plug.link(0).submit(r));
  run(30ms);
  EXPECT_EQ(r.status(), plc::io::RecordStatus::Done);
  EXPECT_EQ(plug.master().counters().global_controls, 1u);
  EXPECT_TRUE(plug.simulated(0)->frozen());
  EXPECT_TRUE(plug.simulated(0)->synced());
  EXPECT_NE(plug.diagnostics(0).find("Freeze_Mode Sync_Mode"), std::string::npos)
      << plug.diagnostics(0);
  // Group 2: not this slave's.
  const std::uint8_t other[2] = {dp::kGcUnfreeze | dp::kGcUnsync, 0x02};
  plc::io::RecordRequest r2;
  ASSERT_TRUE(r2.prepare_write(plc::profibus::kGlobalControlRecord, other));
  ASSERT_TRUE(plug.link(0).submit(r2));
  run(30ms);
  EXPECT_EQ(r2.status(), plc::io::RecordStatus::Done);
  EXPECT_TRUE(plug.simulated(0)->frozen()) << "Group_Select 2 is not the slave's group 1";
  plc::io::RecordRequest bad;
  ASSERT_TRUE(bad.prepare_write(0x0001, gc));
  ASSERT_TRUE(plug.link(0).submit(bad));
  run(10ms);
  EXPECT_EQ(bad.status(), plc::io::RecordStatus::Error);
  EXPECT_EQ(bad.error(), plc::io::RecordError::InvalidIndex);
  plug.stop();
}

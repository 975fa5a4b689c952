// `plcrun --pn-scan / --pn-set-name / --pn-set-ip` (the DCP tool,
// dcp_tool.hpp) in namespace A against build/bin/pndevsim with two devices
// in namespace B (netns.hpp: a fresh veth pair, never a host interface):
// DCP Identify All lists both with their names, addresses and ident
// numbers sorted by MAC (fieldbus-masters.md §1 item 1; the high MAC
// answers first, after (0x0102 mod 64) x 10 ms, the low one after 480 ms);
// DCP Set renames one and the next scan shows it; a bad name is refused
// before anything is sent; the device's Set error code is reported; a
// missing interface gives the link's error.
#include <regex>

#include "netns.hpp"
#include "runtime/test_helpers.hpp"

namespace {

const std::string kLowMac = "02:00:00:00:00:30";
const std::string kHighMac = "02:00:00:00:01:02";

class PnScanNetns : public plctest::NetnsTest {
 protected:
  // 10.88.X.2 -> 10.88.X.<last>
  std::string b_ip(int last) const {
    return b().ip.substr(0, b().ip.rfind('.') + 1) + std::to_string(last);
  }
  plctest::NsRun plcrun(const std::string& args) {
    return pair().run(a(), plctest::plcrun_path() + " " + args + " 2>&1");
  }
  plctest::NsRun scan() { return plcrun("--pn-scan " + a().iface); }
  // Scans until `expect` is in the listing (pndevsim needs a moment to
  // start, more on a loaded machine): 10 scans of 1 s at most. The last
  // listing.
  plctest::NsRun scan_until(const std::string& expect) {
    plctest::NsRun r;
    for (int i = 0; i < 10; ++i) {
      r = scan();
      if (r.output.find(expect) != std::string::npos) break;
    }
    return r;
  }
  std::unique_ptr<plctest::NsProcess> start_sim() {
    // Both device addresses must be the interface's (pndevsim binds UDP
    // 34964 on each).
    EXPECT_EQ(pair().run(b(), "ip addr add " + b_ip(3) + "/24 dev " + b().iface).exit_code, 0);
    const std::string cfg = plctest::write_temp(
        "pn_scan_netns.yaml", "interface: " + b().iface +
                                  "\ncontrol: none\ndevices:\n"
                                  "  - name: safety\n    model: nord_profisafe\n    ip: " +
                                  b_ip(3) + "\n    mac: " + kHighMac +
                                  "\n  - name: conveyor\n    model: hiwin_e1\n"
                                  "    params: {telegram: 111}\n    ip: " +
                                  b().ip + "\n    mac: " + kLowMac + "\n");
    return pair().start(b(), plctest::bin_dir() + "/pndevsim " + cfg);
  }
};

TEST_F(PnScanNetns, ScanListsBothDevicesSortedByMacAndSetNameRenamesOne) {
  auto sim = start_sim();
  ASSERT_TRUE(sim);
  const std::string conveyor = kLowMac + "  conveyor  ip " + b().ip +
                               "/255.255.255.0 gw 0.0.0.0  vendor 0x0fff device 0x0e01  "
                               "role device  type \"softplc pndevsim\"\n";
  const std::string safety = kHighMac + "  safety  ip " + b_ip(3) +
                             "/255.255.255.0 gw 0.0.0.0  vendor 0x0fff device 0x0280  "
                             "role device  type \"softplc pndevsim\"\n";
  // Until both are listed (the low MAC answers last, 480 ms into the 1 s
  // window): the listing checked below is then a complete one.
  auto r = scan_until(conveyor + safety);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2 PROFINET devices answered on " + a().iface + " within 1000 ms:\n" +
                          conveyor + safety),
            std::string::npos)
      << r.output << "\npndevsim:\n"
      << sim->output();

  // A name the codec's NameOfStation rule refuses: exit 2, nothing sent
  // (pndevsim would print "name set" for any Set it took).
  r = plcrun("--pn-set-name " + a().iface + " " + kHighMac + " Safety_1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'Safety_1' is not a valid NameOfStation"), std::string::npos)
      << r.output;
  r = plcrun("--pn-set-name " + a().iface + " " + kHighMac + " safety-renamed");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("plcrun: " + kHighMac + ": NameOfStation set to 'safety-renamed'"),
            std::string::npos)
      << r.output;
  // Until both answer again (a sanitized pndevsim or plcrun stalled for
  // half a second misses one answer of a single 1 s window).
  r = scan_until(conveyor + kHighMac + "  safety-renamed  ip " + b_ip(3) + "/");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(kHighMac + "  safety-renamed  ip " + b_ip(3)), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find(conveyor), std::string::npos) << r.output;

  // Set IP to an address B does not have: pndevsim cannot bind it and
  // answers error 5 "set not possible", which plcrun reports (exit 1).
  r = plcrun("--pn-set-ip " + a().iface + " " + kLowMac + " " + b_ip(9) + "/24");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("refused the Set (option 1/2): error 5"), std::string::npos) << r.output;
  // One it has: taken, and the next scan shows it with the new mask.
  ASSERT_EQ(pair().run(b(), "ip addr add " + b_ip(4) + "/24 dev " + b().iface).exit_code, 0);
  r = plcrun("--pn-set-ip " + a().iface + " " + kLowMac + " " + b_ip(4) + "/16");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = scan_until(kLowMac + "  conveyor  ip " + b_ip(4) + "/255.255.0.0 gw 0.0.0.0");
  EXPECT_NE(r.output.find(kLowMac + "  conveyor  ip " + b_ip(4) + "/255.255.0.0 gw 0.0.0.0"),
            std::string::npos)
      << r.output;

  sim->stop();
  const std::string log = sim->output();
  // The only names set are the good one: the bad one never reached it.
  const std::regex name_set("name set");
  EXPECT_EQ(
      std::distance(std::sregex_iterator(log.begin(), log.end(), name_set), std::sregex_iterator()),
      1)
      << log;
}

TEST_F(PnScanNetns, NoDevicesAndMissingInterfaceAreToldClearly) {
  auto r = scan();  // nothing runs in B
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no PROFINET devices answered on " + a().iface + " within 1000 ms"),
            std::string::npos)
      << r.output;
  r = plcrun("--pn-scan nosuch0");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("plcrun: --pn-scan: raw Ethernet on 'nosuch0': no such interface"),
            std::string::npos)
      << r.output;
  r = plcrun("--pn-set-name nosuch0 " + kLowMac);  // two arguments instead of three
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--pn-set-name takes IFACE MAC NAME"), std::string::npos) << r.output;
}

}  // namespace

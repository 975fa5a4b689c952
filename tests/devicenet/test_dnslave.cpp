// build/bin/dnslave as a process: config errors (file:line:column, exit 2),
// and one dnslave hosting two slaves, the PR5510 (PR1721/34 identity) and
// the VF66B (DNET66-Z identity, assemblies from j09/j10), on a UDP CAN bus
// whose hub it hosts, scanned by a scanner in this test.
#include <gtest/gtest.h>
#include <poll.h>

#include "child_process.hpp"
#include "dn_rig.hpp"
#include "plc/can/udp_bus.hpp"
#include "runtime/test_helpers.hpp"

using namespace dntest;
namespace em = plc::io::explicit_msg;

namespace {
std::string dnslave() { return plctest::bin_dir() + "/dnslave"; }
}  // namespace

TEST(Dnslave, ConfigErrorsNameTheLineAndExitTwo) {
  struct Case {
    const char* yaml;
    const char* message;
  };
  const Case cases[] = {
      {"bus: udp:127.0.0.1:1\nslaves:\n  - {model: pr5510, mac: 64}\n", ":3:"},
      {"bus: udp:127.0.0.1:1\nslaves:\n  - {model: nosuch, mac: 4}\n", "unknown device model"},
      {"bus: udp:127.0.0.1:1\nslaves:\n  - {model: pr5510, mac: 4, params: {bus: can}}\n",
       "params: key 'bus'"},
      {"bus: udp:127.0.0.1:1\nslaves:\n  - {model: pr5510, mac: 4, profil: x}\n",
       "unknown key 'profil'"},
      {"bus: udp:127.0.0.1:1\nslaves: []\n", "at least one slave"},
      {"bus: udp:127.0.0.1:1\nslaves:\n  - {model: pr5510, mac: 4}\n  - {model: pr5510, mac: 4}\n",
       "MAC ID used twice"},
      {"bus: tcp:x\nslaves:\n  - {model: pr5510, mac: 4}\n", "expected socketcan:IFNAME or udp"},
  };
  for (const Case& c : cases) {
    const std::string f = plctest::write_temp("dnslave_bad.yaml", c.yaml);
    const auto r = plctest::run_command(dnslave() + " " + f + " --for 1s");
    EXPECT_EQ(r.exit_code, 2) << c.yaml << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.yaml << r.output;
  }
}

TEST(Dnslave, HostsThePr5510AndTheVf66bOnOneBus) {
  const std::uint16_t port = free_udp_port();
  const std::string yaml = "bus: udp:127.0.0.1:" + std::to_string(port) +
                           "\nhub: true\nslaves:\n"
                           "  - {name: scale, model: pr5510, params: {bus: devicenet}, mac: 5, "
                           "profile: pr1721_34}\n"
                           "  - {name: drive, model: vf66b, params: {j09: 1, j10: 2, b10: 3, b11: "
                           "3}, mac: 7, profile: dnet66z}\n";
  Child slaves({dnslave(), plctest::write_temp("dnslave_two.yaml", yaml), "--for", "20s"});
  ASSERT_TRUE(slaves.wait_for("2 slave(s) on the bus", 5000)) << slaves.all;

  plc::can::UdpBus bus("127.0.0.1", port);
  dn::ScannerConfig c;
  c.dup_mac_wait = 200ms;
  dn::Scanner sc(c, &bus);
  dn::ScanEntry scale;
  scale.mac = 5;
  scale.input_size = scale.output_size = 8;
  scale.vendor = 560;
  scale.product = 1713;
  dn::ScanEntry drive;
  drive.mac = 7;
  drive.input_size = 12;  // assembly 120 (j10 = 2)
  drive.output_size = 4;  // assembly 21 (j09 = 1)
  const auto ds = sc.add(scale), dd = sc.add(drive);
  const plc::TIME t0 = std::chrono::steady_clock::now().time_since_epoch();
  auto tick = [&] {
    sc.tick(std::chrono::steady_clock::now().time_since_epoch() - t0);
    pollfd p{bus.fd(), POLLIN, 0};
    poll(&p, 1, 2);
  };
  auto until = [&](const std::function<bool()>& pred) {
    for (int i = 0; i < 5000 && !pred(); ++i) tick();
    return pred();
  };
  ASSERT_TRUE(until([&] {
    return sc.state(ds) == dn::ScanState::Online && sc.state(dd) == dn::ScanState::Online;
  })) << sc.diagnostics(ds)
      << "\n"
      << sc.diagnostics(dd);
  io::RecordRequest r;
  const std::uint8_t q[] = {1, 1, 2};  // Identity device type: 0x02 AC drive (§1.1)
  r.prepare_read(em::record_index(em::kGetAttributeSingle), q);
  ASSERT_TRUE(sc.link(dd).submit(r));
  ASSERT_TRUE(until([&] { return !r.busy(); }));
  ASSERT_EQ(r.status(), io::RecordStatus::Done);
  EXPECT_EQ(r.data()[0], 0x02);
  EXPECT_EQ(r.data()[1], 0x00);
  EXPECT_EQ(sc.counters(dd).wrong_size, 0u);
  EXPECT_EQ(sc.counters(ds).wrong_size, 0u);
}

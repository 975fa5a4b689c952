// The DCP tool of `plcrun --pn-scan` (dcp_tool.hpp) against two PnDevices on
// the in-memory hub in virtual time: Identify All with ResponseDelayFactor
// 64, answers spread by (MAC mod 64) x 10 ms (IEC 61158-6-10 DCP
// "ResponseDelay"; fieldbus-masters.md §1 item 1) all inside the 1 s
// window, listed sorted by MAC whatever order they came in; Set of
// NameOfStation and its error code; the IP/PREFIX/GATEWAY argument.
#include <sstream>

#include "plc/profinet/controller/dcp_tool.hpp"
#include "plc/profinet/link/open_link.hpp"
#include "test_device_harness.hpp"

namespace pn_test {
namespace {

class DcpTool : public ::testing::Test {
 protected:
  // Low MAC: 0x0030 mod 64 = 48 -> answers after 480 ms. High MAC: 0x0102
  // mod 64 = 2 -> after 20 ms, so the answers come in the reverse order.
  static constexpr pn::Mac kToolMac{0x02, 0, 0, 0, 0, 0x01};
  static constexpr pn::Mac kLowMac{0x02, 0, 0, 0, 0x00, 0x30};
  static constexpr pn::Mac kHighMac{0x02, 0, 0, 0, 0x01, 0x02};

  void SetUp() override {
    tool = hub.port(kToolMac);
    add_device(kHighMac, "echo-high", pn::Ipv4{0x0A000003});
    add_device(kLowMac, "echo-low", pn::Ipv4{0x0A000002});
  }
  void add_device(const pn::Mac& mac, const std::string& name, pn::Ipv4 ip) {
    pn::PnDeviceConfig cfg;
    cfg.description = echo_description();
    cfg.description.station_name = name;
    cfg.description.ip = ip;
    ports.push_back(hub.port(mac));
    devices.push_back(std::make_unique<pn::PnDevice>(
        cfg, std::make_unique<EchoModel>(), *ports.back(),
        [this](pn::Ipv4 a) { return net.port(a, pn::kRpcUdpPort); }));
  }
  // Advances virtual time, polling the devices, and hands the tool's
  // frames to `scan` (else keeps them in `received`).
  void run(nanoseconds d, pn::DcpScan* scan = nullptr) {
    std::array<std::uint8_t, pn::kMaxFrameLength> b{};
    for (nanoseconds end = now + d; now < end;) {
      now += microseconds(500);
      hub.set_time(now);
      net.set_time(now);
      for (auto& dev : devices) dev->poll(now);
      for (int i = 0; i < 100; ++i) {
        const std::size_t n = tool->receive(b, nanoseconds(0));
        if (n == 0) break;
        if (scan)
          scan->on_frame(std::span<const std::uint8_t>(b.data(), n));
        else
          received.emplace_back(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
      }
    }
  }
  // A whole scan in virtual time: request, then the window.
  std::vector<pn::DcpStation> scan_all(std::uint32_t xid) {
    pn::DcpScan scan(kToolMac, xid);
    tool->send(scan.request());
    run(pn::kScanWindow, &scan);
    return scan.stations();
  }

  pn::MemoryEthernet hub;
  pn::MemoryUdp net;
  std::unique_ptr<pn::EthernetPort> tool;
  std::vector<std::unique_ptr<pn::EthernetPort>> ports;
  std::vector<std::unique_ptr<pn::PnDevice>> devices;
  std::vector<std::vector<std::uint8_t>> received;
  nanoseconds now{0};
};

TEST_F(DcpTool, IdentifyAllAnswersSpreadByMacModFactorAllInsideTheWindow) {
  run(milliseconds(1));
  pn::DcpScan scan(kToolMac, 0x1234);
  const auto req = scan.request();
  pn::PnFrameView v;
  pn::DcpMessage m;
  ASSERT_TRUE(pn::decode_pn_frame(req, v));
  EXPECT_EQ(v.dst, pn::kDcpIdentifyMulticast);
  ASSERT_TRUE(pn::decode_dcp(v.frame_id, v.pdu, m));
  EXPECT_EQ(m.response_delay, 64);
  EXPECT_FALSE(pn::identify_filter(m).has_value());  // all
  tool->send(req);
  run(milliseconds(470), &scan);  // the high MAC (20 ms) has answered, the low (480 ms) not yet
  ASSERT_EQ(scan.stations().size(), 1u);
  EXPECT_EQ(scan.stations()[0].mac, kHighMac);
  run(milliseconds(20), &scan);
  const auto st = scan.stations();
  ASSERT_EQ(st.size(), 2u);
  EXPECT_EQ(st[0].mac, kLowMac);  // sorted by MAC, not by arrival
  EXPECT_EQ(st[1].mac, kHighMac);
  EXPECT_EQ(scan.bad(), 0u);
  // The latest possible answer, (63 mod 64) x 10 ms, is inside the window.
  EXPECT_GT(pn::kScanWindow, milliseconds(10 * (pn::kScanResponseDelayFactor - 1)));
}

TEST_F(DcpTool, ListingIsOneLinePerDeviceSortedByMac) {
  const auto st = scan_all(7);
  EXPECT_EQ(pn::format_scan(st, "pna", pn::kScanWindow),
            "2 PROFINET devices answered on pna within 1000 ms:\n"
            "02:00:00:00:00:30  echo-low  ip 10.0.0.2/255.255.255.0 gw 0.0.0.0  vendor 0x0fff "
            "device 0x0042  role device  type \"softplc pndevsim\"\n"
            "02:00:00:00:01:02  echo-high  ip 10.0.0.3/255.255.255.0 gw 0.0.0.0  vendor 0x0fff "
            "device 0x0042  role device  type \"softplc pndevsim\"\n");
  EXPECT_EQ(pn::format_scan({}, "pna", pn::kScanWindow),
            "no PROFINET devices answered on pna within 1000 ms\n");
  pn::DcpStation unnamed;
  unnamed.id.device_role = pn::dcp::kRoleDevice | pn::dcp::kRoleController;
  EXPECT_NE(pn::format_station(unnamed).find("  (none)  "), std::string::npos);
  EXPECT_EQ(pn::role_text(0x03), "device+controller");
  EXPECT_EQ(pn::role_text(0x00), "0x0000");
}

TEST_F(DcpTool, AnswersToAnotherXidOrAnotherStationAreNotListed) {
  pn::DcpScan scan(kToolMac, 1);
  tool->send(pn::encode_dcp_identify_request(kToolMac, 2, std::nullopt, 64));  // other Xid
  run(pn::kScanWindow, &scan);
  EXPECT_TRUE(scan.stations().empty());
  // An answer addressed to another station is not ours either.
  pn::DcpIdentity id;
  id.station_name = "x";
  scan.on_frame(pn::encode_dcp_identify_response(kLowMac, kHighMac, 1, id));
  EXPECT_TRUE(scan.stations().empty());
}

TEST_F(DcpTool, SetNameIsAnsweredOkAndTheNextScanShowsIt) {
  pn::DcpSetRequest req;
  req.station_name = "renamed";
  tool->send(pn::encode_dcp_set_request(kLowMac, kToolMac, 42, req));
  run(milliseconds(1));
  // The Set response: Control/Response for Device/NameOfStation, error 0.
  ASSERT_EQ(received.size(), 1u);
  pn::PnFrameView v;
  pn::DcpMessage m;
  std::vector<pn::DcpSetResult> results;
  ASSERT_TRUE(pn::decode_pn_frame(received[0], v));
  ASSERT_TRUE(pn::decode_dcp(v.frame_id, v.pdu, m));
  ASSERT_TRUE(pn::set_results_from(m, results));
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].suboption, pn::dcp::kSubDeviceNameOfStation);
  EXPECT_EQ(results[0].error, pn::dcp::kErrorOk);
  const auto st = scan_all(8);
  ASSERT_EQ(st.size(), 2u);
  EXPECT_EQ(st[0].id.station_name, "renamed");
  EXPECT_EQ(st[1].id.station_name, "echo-high");
}

TEST(DcpToolArgs, IpSuiteIsIpPrefixGatewayWithDefaults) {
  std::string why;
  auto s = pn::parse_ip_suite("192.168.0.10", why);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->ip, 0xC0A8000Au);
  EXPECT_EQ(s->netmask, 0xFFFFFF00u);
  EXPECT_EQ(s->gateway, 0u);
  s = pn::parse_ip_suite("10.1.2.3/16/10.1.0.1", why);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->netmask, 0xFFFF0000u);
  EXPECT_EQ(s->gateway, 0x0A010001u);
  s = pn::parse_ip_suite("10.1.2.3/32", why);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->netmask, 0xFFFFFFFFu);
  for (const char* bad : {"", "10.1.2", "10.1.2.3/0", "10.1.2.3/33", "10.1.2.3/x", "10.1.2.3/24/",
                          "10.1.2.3/24/1.2.3.4/5", "0.0.0.0"})
    EXPECT_FALSE(pn::parse_ip_suite(bad, why)) << bad;
}

// Bad arguments are refused before the interface is even opened: exit 2,
// nothing sent (the interface "mem:..." would otherwise be created).
TEST(DcpToolArgs, BadNameOrMacIsRefusedBeforeAnythingIsSent) {
  std::ostringstream out, err;
  EXPECT_EQ(pn::pn_set_name_command("mem:dcp-tool-bad", "02:00:00:00:00:30", "Bad_Name", out, err),
            2);
  EXPECT_NE(err.str().find("'Bad_Name' is not a valid NameOfStation"), std::string::npos)
      << err.str();
  EXPECT_NE(err.str().find("nothing sent"), std::string::npos);
  EXPECT_EQ(pn::memory_ethernet("dcp-tool-bad").frames_carried(), 0u);
  err.str("");
  EXPECT_EQ(pn::pn_set_ip_command("mem:dcp-tool-bad", "02:00:00:00:00", "10.0.0.1", out, err), 2);
  EXPECT_NE(err.str().find("is not a MAC address"), std::string::npos) << err.str();
  EXPECT_EQ(pn::memory_ethernet("dcp-tool-bad").frames_carried(), 0u);
  pn::forget_memory_link("dcp-tool-bad");
}

}  // namespace
}  // namespace pn_test

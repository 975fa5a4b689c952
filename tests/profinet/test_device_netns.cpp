// build/bin/pndevsim as a process in one network namespace, a controller
// made of the wire codec and the real transports in the other (netns.hpp:
// a fresh veth pair, never a host interface): DCP Identify (fieldbus-
// masters.md §1 item 1) is answered over a real interface, a Connect (item
// 2) is accepted and input frames start, and pndevsim prints its state
// changes (connected, then lost when no output frames come).
//
// A CI machine may stall any process for tens of ms: the AR's data hold is
// 500 ms (not the 3 ms a bench would use), and every wait is on a condition
// (a frame, a line in pndevsim's log) up to a deadline of seconds, never a
// window of wall time that the other process must hit.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <thread>

#include "netns.hpp"
#include "plc/profinet/description/builtin_descriptions.hpp"
#include "plc/profinet/link/open_link.hpp"
#include "plc/profinet/link/socket_udp_port.hpp"
#include "runtime/test_helpers.hpp"
#include "test_device_harness.hpp"

namespace pn = plc::profinet;
using namespace std::chrono_literals;

namespace {

using Clock = std::chrono::steady_clock;

// 1 ms x 500: a data hold that no stall of a loaded machine reaches.
constexpr std::uint16_t kDataHoldFactor = 500;

class DeviceNetns : public plctest::NetnsTest {
 protected:
  // Asks for `name` every 100 ms (pndevsim needs a moment to start), 10 s
  // at most; the identity and the device's MAC, nullopt if none answered.
  static std::optional<std::pair<pn::DcpIdentity, pn::Mac>> identify(pn::EthernetPort& eth,
                                                                     const std::string& name) {
    std::vector<std::uint8_t> buf(pn::kMaxFrameLength);
    const auto end = Clock::now() + 10s;
    for (std::uint16_t i = 0; i < 1000 && Clock::now() < end; ++i) {
      eth.send(pn::encode_dcp_identify_request(eth.mac(), 100 + i, name, 1));
      const auto next = Clock::now() + 100ms;
      for (int k = 0; k < 1000 && Clock::now() < next; ++k) {
        const std::size_t n = eth.receive(buf, 5ms);
        pn::PnFrameView v;
        pn::DcpMessage m;
        pn::DcpIdentity id;
        if (n && pn::decode_pn_frame(std::span(buf.data(), n), v) &&
            v.frame_id == pn::frame_id::kDcpIdentifyResponse &&
            pn::decode_dcp(v.frame_id, v.pdu, m) && pn::identity_from(m, id))
          return std::make_pair(id, v.src);
      }
    }
    return std::nullopt;
  }
  // One RPC call over UDP; the PNIO status (0xFFFFFFFF: no answer in 1 s).
  static pn::PnioStatus call(pn::UdpPort& udp, pn::Ipv4 to, std::uint16_t opnum,
                             const std::vector<std::uint8_t>& args, std::uint32_t activity,
                             pn::ConnectResponse* res = nullptr) {
    pn::RpcHeader h;
    h.object = pn::pnio_object_uuid(1, pn::kHiwinE1DeviceId, pn::kOurVendorId);
    h.interface = pn::kPnioDeviceInterface;
    h.activity = pn::Uuid{activity, 1, 2, {3, 4, 5, 6, 7, 8, 9, 10}};
    h.opnum = opnum;
    udp.send_to(to, pn::kRpcUdpPort,
                pn::encode_rpc(h, pn::encode_ndr_request(pn::rpc::kMaxArgs, args)));
    std::vector<std::uint8_t> d(pn::kMaxDatagram);
    pn::Ipv4 from;
    std::uint16_t port = 0;
    d.resize(udp.receive_from(d, from, port, 1s));
    pn::RpcPdu pdu;
    pn::NdrResponse ndr;
    if (!pn::decode_rpc(d, pdu) ||
        !pn::decode_ndr_response(pdu.body, pdu.header.little_endian, ndr))
      return pn::PnioStatus::from(0xFFFFFFFF);
    if (res && ndr.status.ok()) {
      EXPECT_TRUE(pn::decode_connect_response(ndr.args, *res));
    }
    return ndr.status;
  }
  static pn::PnioStatus connect(pn::UdpPort& udp, pn::Ipv4 to, const pn::ConnectRequest& req,
                                std::uint32_t activity, pn::ConnectResponse* res = nullptr) {
    return call(udp, to, pn::rpc::kOpConnect, pn::encode_connect_request(req), activity, res);
  }
  static pn::ConnectRequest e1_request(const pn::Mac& ctl) {
    plc::io::ModelParams p;
    p.set("telegram", "111");
    pn::ConnectRequest r =
        pn_test::make_connect_request(pn::builtin_description("hiwin_e1", p), ctl);
    for (auto& c : r.iocrs) c.watchdog_factor = c.data_hold_factor = kDataHoldFactor;
    return r;
  }
  // Waits until pndevsim's log holds `text`: 10 s at most (its main thread
  // prints a state change within tens of ms on an idle machine).
  static bool wait_log(plctest::NsProcess& sim, const std::string& text) {
    const auto end = Clock::now() + 10s;
    for (int i = 0; i < 10000 && Clock::now() < end; ++i) {
      if (sim.output().find(text) != std::string::npos) return true;
      if (sim.wait(20ms) != -1) break;  // returns early only when it ends
    }
    return sim.output().find(text) != std::string::npos;
  }
};

TEST_F(DeviceNetns, PndevsimAnswersIdentifyAndConnectAcrossNamespaces) {
  const std::string cfg = plctest::write_temp(
      "pndevsim_netns.yaml", "interface: " + b().iface +
                                 "\ncontrol: none\ndevices:\n  - name: conveyor\n"
                                 "    model: hiwin_e1\n    params: {telegram: 111}\n"
                                 "    ip: " +
                                 b().ip + "\n");
  auto sim = pair().start(b(), plctest::bin_dir() + "/pndevsim " + cfg);
  ASSERT_TRUE(sim);

  auto eth = pair().in(a(), [&] { return pn::open_ethernet(a().iface); });
  auto udp = pair().in(a(), [&] {
    return std::make_unique<pn::SocketUdpPort>(*pn::parse_ipv4(a().ip), pn::kRpcUdpPort);
  });
  const auto found = identify(*eth, "conveyor");
  ASSERT_TRUE(found.has_value()) << "no DCP Identify answer from pndevsim";
  const pn::Mac dev_mac = found->second;
  EXPECT_EQ(found->first.station_name, "conveyor");
  EXPECT_EQ(pn::to_string(pn::Ipv4{found->first.ip.ip}), b().ip);
  EXPECT_EQ(found->first.vendor_id, pn::kOurVendorId);
  EXPECT_EQ(found->first.device_id, pn::kHiwinE1DeviceId);

  // Connect over UDP 34964: accepted, and input frames start at once.
  const auto req = e1_request(eth->mac());
  pn::ConnectResponse res;
  ASSERT_TRUE(connect(*udp, *pn::parse_ipv4(b().ip), req, 0xACAC0001, &res).ok());
  std::vector<std::uint8_t> buf(pn::kMaxFrameLength);
  std::uint16_t out_id = 0;
  for (const auto& c : res.iocrs)
    if (c.iocr_type == pn::iocr::kTypeOutput) out_id = c.frame_id;
  pn::IocrLayout out;
  ASSERT_TRUE(pn::layout_from_iocr(req.iocrs[1], req.expected, out));
  // Answer each of its first input frames with an output frame, then stop.
  int cyclic = 0;
  for (int k = 0; k < 200 && cyclic < 5; ++k) {
    const std::size_t n = eth->receive(buf, 10ms);
    pn::PnFrameView v;
    if (!n || !pn::decode_pn_frame(std::span(buf.data(), n), v) || v.frame_id != 0xC001 ||
        v.src != dev_mac)
      continue;
    ++cyclic;
    std::vector<std::uint8_t> c_sdu(out.c_sdu_length, 0);
    for (const auto& o : out.data) pn::put_io_data(c_sdu, o, {}, pn::iocr::kIoxsGood);
    pn::CyclicHeader ch;
    ch.dst = dev_mac;
    ch.src = eth->mac();
    ch.frame_id = out_id;
    ch.cycle_counter = static_cast<std::uint16_t>(32 * cyclic);
    std::vector<std::uint8_t> f(pn::kMaxFrameLength);
    f.resize(pn::encode_cyclic(f, ch, c_sdu));
    eth->send(f);
  }
  EXPECT_EQ(cyclic, 5);

  // Our output frames stopped: its data-hold watchdog drops the AR, and it
  // says so.
  const std::string lost = "pndevsim: conveyor: lost (data hold expired)";
  EXPECT_TRUE(wait_log(*sim, lost)) << sim->output();
  sim->stop();
  const std::string log = sim->output();
  EXPECT_NE(log.find("pndevsim: conveyor: connected"), std::string::npos) << log;
  EXPECT_NE(log.find(lost), std::string::npos) << log;
}

// The control FIFO switches a fault at run time: Connects are refused with
// the given status, then accepted again.
TEST_F(DeviceNetns, ControlFifoSwitchesRefuseConnectAtRunTime) {
  const std::string fifo = "/tmp/pndevsim_ctl_" + std::to_string(getpid()) + ".fifo";
  const std::string cfg = plctest::write_temp(
      "pndevsim_fifo.yaml", "interface: " + b().iface + "\ncontrol: " + fifo +
                                "\ndevices:\n  - name: conveyor\n    model: hiwin_e1\n"
                                "    params: {telegram: 111}\n    ip: " +
                                b().ip + "\n");
  auto sim = pair().start(b(), plctest::bin_dir() + "/pndevsim " + cfg);
  ASSERT_TRUE(sim);
  auto eth = pair().in(a(), [&] { return pn::open_ethernet(a().iface); });
  auto udp = pair().in(a(), [&] {
    return std::make_unique<pn::SocketUdpPort>(*pn::parse_ipv4(a().ip), pn::kRpcUdpPort);
  });
  ASSERT_TRUE(identify(*eth, "conveyor").has_value());  // running, FIFO open
  auto command = [&](const std::string& line) { std::ofstream(fifo) << line << std::endl; };
  const auto req = e1_request(eth->mac());
  const pn::Ipv4 dev = *pn::parse_ipv4(b().ip);
  command("refuse conveyor DB810107");
  pn::PnioStatus st;
  // The command takes effect within a few tens of ms on an idle machine;
  // try for 10 s at most, 100 ms apart (a loaded CI machine starves the
  // simulator's control thread).
  auto end = Clock::now() + 10s;
  for (std::uint32_t i = 0; i < 100 && st.value() != 0xDB810107u && Clock::now() < end; ++i) {
    if (i > 0) (void)sim->wait(100ms);  // returns early only when it ends
    st = connect(*udp, dev, req, 0xF1F00000 + i);
    if (st.ok()) {  // the command came too late for this one: release it
      pn::ControlBlock c;
      c.block_type = pn::block::kReleaseReq;
      c.ar_uuid = req.ar.ar_uuid;
      c.session_key = req.ar.session_key;
      c.command = pn::control::kRelease;
      (void)call(*udp, dev, pn::rpc::kOpRelease, pn::encode_control(c), 0xF2F00000 + i);
    }
  }
  EXPECT_EQ(st.value(), 0xDB810107u);
  command("refuse conveyor off");
  end = Clock::now() + 10s;
  for (std::uint32_t i = 0; i < 100 && !st.ok() && Clock::now() < end; ++i) {
    if (i > 0) (void)sim->wait(100ms);
    st = connect(*udp, dev, req, 0xF3F00000 + i);
  }
  EXPECT_TRUE(st.ok()) << std::hex << st.value();
  EXPECT_TRUE(wait_log(*sim, "pndevsim: conveyor: connected")) << sim->output();
  sim->stop();
  std::remove(fifo.c_str());
  const std::string log = sim->output();
  EXPECT_NE(log.find("pndevsim: conveyor: refused DB810107"), std::string::npos) << log;
  EXPECT_NE(log.find("pndevsim: conveyor: connected"), std::string::npos) << log;
}

TEST(Pndevsim, ConfigErrorsNameTheLineAndExitTwo) {
  struct Case {
    const char* yaml;
    const char* message;
  };
  const Case cases[] = {
      {"interface: lo\ndevices:\n  - {model: hiwin_e1, ip: 10.0.0.2, params: {telegram: 112}}\n",
       ":3:"},
      {"interface: lo\ndevices:\n  - {model: nosuch, ip: 10.0.0.2}\n", "unknown device model"},
      {"interface: lo\ndevices:\n  - {model: hiwin_e1, ipp: 10.0.0.2}\n", "unknown key 'ipp'"},
      {"interface: lo\ndevices:\n  - {model: hiwin_e1, ip: 10.0.0.300}\n", "not an IPv4 address"},
      {"interface: lo\ndevices: []\n", "at least one device"},
      {"interface: lo\ndevices:\n  - {model: hiwin_e1, ip: 10.0.0.2, faults: {refuse_connect: "
       "xyz}}\n",
       "8 hex digits"},
      {"devices:\n  - {model: hiwin_e1, ip: 10.0.0.2}\n", "key 'interface' missing"},
      {"interface: plcpn_nosuch0\ndevices:\n  - {model: hiwin_e1, ip: 10.0.0.2}\n",
       "no such interface"},
  };
  // The filling cell's example is a valid config: only the interface is
  // missing here.
  std::ifstream in(plctest::source_path("programs/filling_cell/pndevsim.yaml"));
  std::string example((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_NE(example.find("interface: pnb"), std::string::npos);
  example.replace(example.find("interface: pnb"), 14, "interface: plcpn_nosuch0");
  const auto r = plctest::run_command(plctest::bin_dir() + "/pndevsim " +
                                      plctest::write_temp("pndevsim_cell.yaml", example));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no such interface"), std::string::npos) << r.output;

  for (const Case& c : cases) {
    const std::string f = plctest::write_temp("pndevsim_bad.yaml", c.yaml);
    const auto r = plctest::run_command(plctest::bin_dir() + "/pndevsim " + f + " --for 1s");
    EXPECT_EQ(r.exit_code, 2) << c.yaml << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.yaml << r.output;
  }
}

}  // namespace

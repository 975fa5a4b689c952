// Scanner and slave in one process on the CAN-over-UDP transport (a hub on
// 127.0.0.1), in real time: allocation, explicit (fragmented), polled I/O,
// the slave falling silent (lost) and coming back (re-allocated). The
// lockstep tests (test_devicenet_scanner) check the timing rules exactly;
// this one checks that the same protocol runs over real sockets. Loops are
// bounded by count; each wait is a poll() on the sockets for at most 2 ms.
#include <gtest/gtest.h>
#include <poll.h>
#include <time.h>

#include "dn_rig.hpp"
#include "plc/can/udp_bus.hpp"

using namespace dntest;
namespace em = plc::io::explicit_msg;

namespace {

TIME mono() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
}

struct UdpRig {
  plc::can::UdpHub hub{"127.0.0.1", 0};
  plc::can::UdpBus master_bus{"127.0.0.1", hub.port()};
  plc::can::UdpBus slave_bus{"127.0.0.1", hub.port()};
  dn::Scanner scanner;
  dn::Slave slave;
  TestModel* model;
  const TIME t0 = mono();

  UdpRig(dn::ScannerConfig c, std::unique_ptr<TestModel> m, dn::SlaveConfig sc)
      : scanner(c, &master_bus), slave(sc, std::move(m), slave_bus), model(nullptr) {}

  void tick() {
    const TIME now = mono() - t0;
    scanner.tick(now);
    slave.tick(now);
    pollfd p[2] = {{master_bus.fd(), POLLIN, 0}, {slave_bus.fd(), POLLIN, 0}};
    poll(p, 2, 2);
  }
  bool run_until(const std::function<bool()>& pred, int max_ticks) {
    for (int i = 0; i < max_ticks; ++i) {
      if (pred()) return true;
      tick();
    }
    return pred();
  }
};

}  // namespace

TEST(DeviceNetUdp, AllocatePollExplicitLoseAndReallocate) {
  dn::ScannerConfig c;
  c.dup_mac_wait = std::chrono::milliseconds(100);
  c.retry = std::chrono::milliseconds(100);
  dn::SlaveConfig sc;
  sc.mac = 12;
  sc.dup_mac_wait = std::chrono::milliseconds(100);
  sc.identity.vendor = 560;
  sc.identity.product_name = "System Weighing Controller";
  auto m = std::make_unique<TestModel>(12, 8);
  TestModel* model = m.get();
  UdpRig r(c, std::move(m), sc);
  dn::ScanEntry e;
  e.name = "scale";
  e.mac = 12;
  e.input_size = 12;  // fragmented responses
  e.output_size = 8;
  e.vendor = 560;
  // Connection timeout 4 x EPR = 1 s: one thread ticks both ends (and the
  // hub forwards on its own), so a stall of that long on a loaded machine
  // would be a loss the test did not make.
  e.epr = std::chrono::milliseconds(250);
  const auto d = r.scanner.add(e);
  auto online = [&] { return r.scanner.state(d) == dn::ScanState::Online; };

  ASSERT_TRUE(r.run_until(online, 5000)) << r.scanner.diagnostics(d);
  r.scanner.outputs(d)[5] = 0x77;
  ASSERT_TRUE(r.run_until([&] { return r.scanner.inputs(d)[5] == 0x77; }, 2000));
  EXPECT_EQ(model->last_outputs.at(5), 0x77);

  io::RecordRequest req;
  std::array<std::uint8_t, 3> q{1, 1, 7};  // product name: a fragmented answer with acks
  ASSERT_TRUE(req.prepare_read(em::record_index(em::kGetAttributeSingle), q));
  ASSERT_TRUE(r.scanner.link(d).submit(req));
  ASSERT_TRUE(r.run_until([&] { return !req.busy(); }, 2000));
  ASSERT_EQ(req.status(), io::RecordStatus::Done);
  EXPECT_EQ(req.data().size(), 27u);

  r.slave.faults().silent = true;
  ASSERT_TRUE(r.run_until([&] { return !online(); }, 5000));
  EXPECT_EQ(r.scanner.link(d).live_state(), io::DeviceState::Offline);
  EXPECT_EQ(r.scanner.inputs(d)[5], 0);
  r.slave.faults().silent = false;
  ASSERT_TRUE(r.run_until(online, 5000)) << r.scanner.diagnostics(d);
  EXPECT_EQ(r.scanner.counters(d).allocations, 2u);
  EXPECT_EQ(r.scanner.counters(d).losses, 1u);
  EXPECT_EQ(r.master_bus.counters().rx_bad, 0u);
}

// The PR5510 on its PR1721/34 DeviceNet card (sartorius-pr1721.md §2):
// the simulated PR5510 behind a DeviceNet slave with the card's identity
// and I/O (EDS §2.3: vendor 560, product type 12, product code 1713,
// revision 1.3, polled I/O of 8 bytes each way through assemblies 100 and
// 150), scanned by the DeviceNet master in lockstep virtual time; the
// weighing blocks, unchanged, run batches over it in the DeviceNet byte
// order (spec §3).
#include <gtest/gtest.h>

#include "dn_rig.hpp"
#include "plc/devicenet/slave_profiles.hpp"
#include "plc/fb/weighing/batch_weigh.hpp"
#include "plc/fb/weighing/pr5510_device.hpp"
#include "pr5510/pr5510_model.hpp"

using namespace dntest;
namespace wg = plc::weighing;
namespace em = plc::io::explicit_msg;

namespace {

struct ScaleOnDeviceNet {
  std::shared_ptr<plc::can::MemWire> wire = plc::can::MemWire::create();
  std::unique_ptr<plc::can::Bus> mbus = wire->attach(), sbus = wire->attach();
  dn::Scanner scanner{dn::ScannerConfig{}, mbus.get()};
  std::unique_ptr<dn::Slave> slave;
  std::size_t d = 0;
  wg::PR5510_Device dev;
  plc::ScanContext ctx{};

  ScaleOnDeviceNet() {
    plc::sim::Pr5510Config c;
    c.bus = wg::Bus::DeviceNet;
    c.filling.seed = 12;
    auto cfg = dn::slave_profile("pr1721_34");
    cfg->mac = 5;
    cfg->identity.serial = 5510;
    slave = std::make_unique<dn::Slave>(*cfg, std::make_unique<plc::sim::Pr5510Model>(c), *sbus);
    dn::ScanEntry e;
    e.mac = 5;
    e.input_size = e.output_size = 8;
    e.vendor = 560;
    e.product = 1713;
    d = scanner.add(e);
    dev.port.bind(scanner.inputs(d), scanner.outputs(d), &scanner.link(d));
    dev.BusType = wg::Bus::DeviceNet;
    ctx.period = 1ms;
  }
  // One 1 ms scan: the device block, the body, then the bus and the slave.
  template <class F>
  void scan(F&& body) {
    ctx.now += 1ms;
    dev(ctx);
    body();
    scanner.tick(ctx.now);
    slave->tick(ctx.now);
    ++ctx.cycle;
  }
  template <class P, class F>
  bool run_until(P&& pred, TIME limit, F&& body) {
    const TIME start = ctx.now;
    while (ctx.now - start < limit) {
      scan(body);
      if (pred()) return true;
    }
    return false;
  }
  std::vector<std::uint8_t> get(std::uint8_t cls, std::uint8_t inst, std::uint8_t attr) {
    io::RecordRequest r;
    const std::uint8_t q[] = {cls, inst, attr};
    r.prepare_read(em::record_index(em::kGetAttributeSingle), q);
    EXPECT_TRUE(scanner.link(d).submit(r));
    run_until([&] { return !r.busy(); }, 2s, [] {});
    EXPECT_EQ(r.status(), io::RecordStatus::Done);
    return {r.data().begin(), r.data().end()};
  }
};

}  // namespace

TEST(Pr5510DeviceNet, IdentityAndAssembliesOfTheEds) {
  ScaleOnDeviceNet s;
  ASSERT_TRUE(s.run_until([&] { return s.dev.Online; }, 5s, [] {})) << s.scanner.diagnostics(s.d);
  EXPECT_EQ(s.get(1, 1, 1), (std::vector<std::uint8_t>{0x30, 0x02}));  // VendCode 560
  EXPECT_EQ(s.get(1, 1, 2), (std::vector<std::uint8_t>{12, 0}));       // ProdType 12
  EXPECT_EQ(s.get(1, 1, 3), (std::vector<std::uint8_t>{0xB1, 0x06}));  // ProdCode 1713
  EXPECT_EQ(s.get(1, 1, 4), (std::vector<std::uint8_t>{1, 3}));        // MajRev 1, MinRev 3
  const auto name = s.get(1, 1, 7);
  EXPECT_EQ(std::string(name.begin() + 1, name.end()), "System Weighing Controller");
  // Input1 path 20 04 24 64 30 03 (assembly 100, attr 3), Output1 24 96 (150): 8 bytes each.
  EXPECT_EQ(s.get(4, 100, 3).size(), 8u);
  EXPECT_EQ(s.get(4, 150, 3).size(), 8u);
  EXPECT_EQ(s.get(5, 2, 7), (std::vector<std::uint8_t>{8, 0}));
  EXPECT_EQ(s.get(5, 2, 8), (std::vector<std::uint8_t>{8, 0}));
}

TEST(Pr5510DeviceNet, BatchWeighingBlocksRunUnchangedOverTheScanner) {
  ScaleOnDeviceNet s;
  wg::PR5510_BatchWeigh b;
  b.Device = &s.dev;
  b.TargetWeight = 20.0f;
  b.FineSwitchPoint = 3.0f;
  b.Preact = 0.15f;
  b.TolPlus = b.TolMinus = 0.05f;
  b.EmptyWeight = 0.05f;
  b.MaxFillTime = 30s;
  ASSERT_TRUE(s.run_until([&] { return s.dev.Online; }, 5s, [&] { b(s.ctx); }));
  s.run_until([] { return false; }, 300ms, [&] { b(s.ctx); });
  for (int i = 0; i < 5; ++i) {
    b.Execute = true;
    ASSERT_TRUE(s.run_until([&] { return b.Done || b.Error; }, 60s, [&] { b(s.ctx); }));
    ASSERT_TRUE(b.Done) << "batch " << i << " ErrorID " << b.ErrorID;
    EXPECT_NEAR(b.LastNet, 20.0f, 0.1f);
    b.Execute = false;
    s.scan([&] { b(s.ctx); });
  }
  EXPECT_EQ(b.BatchCount, 5);
  EXPECT_EQ(s.scanner.counters(s.d).losses, 0u);
  EXPECT_EQ(s.scanner.counters(s.d).wrong_size, 0u);
}

// The slave pulled mid-batch: the device block goes off line, the batch
// block reports DeviceOffline; the slave back: re-allocated, batches go on.
TEST(Pr5510DeviceNet, LostScaleIsReportedAndRecovers) {
  ScaleOnDeviceNet s;
  wg::PR5510_BatchWeigh b;
  b.Device = &s.dev;
  b.TargetWeight = 20.0f;
  b.FineSwitchPoint = 3.0f;
  b.TolPlus = b.TolMinus = 0.05f;
  b.MaxFillTime = 30s;
  ASSERT_TRUE(s.run_until([&] { return s.dev.Online; }, 5s, [&] { b(s.ctx); }));
  b.Execute = true;
  s.run_until([] { return false; }, 1s, [&] { b(s.ctx); });
  ASSERT_TRUE(b.Busy);
  s.slave->faults().silent = true;
  ASSERT_TRUE(s.run_until([&] { return b.Error; }, 1s, [&] { b(s.ctx); }));
  EXPECT_EQ(b.ErrorID, wg::error_id::kDeviceOffline);
  EXPECT_FALSE(s.dev.Online);
  b.Execute = false;
  s.slave->faults().silent = false;
  ASSERT_TRUE(s.run_until([&] { return s.dev.Online; }, 10s, [&] { b(s.ctx); }));
  EXPECT_EQ(s.scanner.counters(s.d).allocations, 2u);
}

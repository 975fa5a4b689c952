// A DP master and DP slaves on an in-memory PROFIBUS line, stepped in
// lockstep with a virtual clock: deterministic, no sleeping. RawMaster
// speaks to a slave telegram by telegram (the slave's state machine alone).
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <vector>

#include "plc/io/device_model.hpp"
#include "plc/profibus/dp/cfg.hpp"
#include "plc/profibus/dp/services.hpp"
#include "plc/profibus/fdl/deframer.hpp"
#include "plc/profibus/link/mem_line.hpp"
#include "plc/profibus/master/dp_master.hpp"
#include "plc/profibus/slave/dp_slave.hpp"

namespace pbtest {

using namespace std::chrono_literals;
namespace pb = plc::profibus;
namespace fdl = plc::profibus::fdl;
namespace dp = plc::profibus::dp;
namespace io = plc::io;
using plc::TIME;

// A test device: inputs = outputs with byte 0 counting its steps.
class EchoModel final : public io::DeviceModel {
 public:
  explicit EchoModel(std::size_t n) : n_(n) {}
  std::size_t input_size() const override { return n_; }
  std::size_t output_size() const override { return n_; }
  void step(TIME, TIME, std::span<const std::uint8_t> from, std::span<std::uint8_t> to) override {
    for (std::size_t i = 0; i < to.size(); ++i) to[i] = i < from.size() ? from[i] : 0;
    if (!to.empty()) to[0] = static_cast<std::uint8_t>(++steps);
    last_outputs.assign(from.begin(), from.end());
  }
  void io_connection_lost() override { ++connection_losses; }
  std::size_t n_;
  unsigned steps = 0;
  int connection_losses = 0;
  std::vector<std::uint8_t> last_outputs;
};

// The PR1721/31 identity and modules (sartorius-pr1721.md §1.2).
inline pb::slave::SlaveConfig pr1721_slave(std::uint8_t address, std::size_t io_bytes = 8) {
  pb::slave::SlaveConfig c;
  c.address = address;
  c.ident = 0x5610;
  c.input_bytes = c.output_bytes = io_bytes;
  c.modules = {0xB7, 0xBF, 0x37, 0x3F, 0xF3, 0xF7, 0xFF, 0x73, 0x77, 0x7F};
  c.max_modules = 4;
  return c;
}

inline pb::master::SlaveEntry pr1721_entry(std::uint8_t address, std::uint32_t wd_ms = 100) {
  pb::master::SlaveEntry e;
  e.name = "scale";
  e.address = address;
  e.prm.ident = 0x5610;
  e.prm.station_status = dp::kPrmLockReq | dp::kPrmWdOn | dp::kPrmFreezeReq | dp::kPrmSyncReq;
  const auto [f1, f2] = dp::watchdog_factors(wd_ms);
  e.prm.wd_fact1 = f1;
  e.prm.wd_fact2 = f2;
  e.prm.min_tsdr = 11;
  e.prm.group = 0x01;
  e.cfg = {0xB7};
  e.input_bytes = e.output_bytes = 8;
  return e;
}

struct SlaveNode {
  std::unique_ptr<pb::link::Line> line;
  std::unique_ptr<pb::slave::DpSlave> slave;
  EchoModel* model = nullptr;
  bool running = true;  // false: the process is gone (not ticked)
};

struct Rig {
  std::shared_ptr<pb::link::MemBus> bus = pb::link::MemBus::create();
  std::unique_ptr<pb::link::Line> master_line = bus->attach();
  pb::master::MasterConfig cfg;
  std::unique_ptr<pb::master::DpMaster> master;
  std::vector<std::unique_ptr<SlaveNode>> slaves;
  TIME now{0};
  bool master_running = true;

  Rig() {
    cfg.address = 1;
    cfg.bus = fdl::bus_parameters(1500000, {}, 1, 8);
    cfg.cycle = 2ms;
    cfg.retry = 100ms;
    master = std::make_unique<pb::master::DpMaster>(cfg, master_line.get());
  }
  SlaveNode& add_slave(const pb::slave::SlaveConfig& c) {
    auto n = std::make_unique<SlaveNode>();
    n->line = bus->attach();
    auto m = std::make_unique<EchoModel>(8);
    n->model = m.get();
    n->slave = std::make_unique<pb::slave::DpSlave>(c, std::move(m), *n->line);
    slaves.push_back(std::move(n));
    return *slaves.back();
  }
  // One millisecond: the master and the slaves in turns until the bus is
  // quiet (every request answered or timed out).
  void step(TIME dt = 1ms) {
    now += dt;
    for (int i = 0; i < 64; ++i) {
      const auto before = master->telegrams_sent();
      if (master_running) master->tick(now);
      for (auto& s : slaves)
        if (s->running) s->slave->tick(now);
      if (master_running) master->tick(now);
      if (master->telegrams_sent() == before) break;
    }
  }
  template <class P>
  bool run_until(P&& pred, TIME limit) {
    const TIME start = now;
    while (now - start < limit) {
      step();
      if (pred()) return true;
    }
    return false;
  }
  void run_for(TIME t) {
    run_until([] { return false; }, t);
  }
};

// A master of our own making, telegram by telegram, to one slave.
struct RawMaster {
  std::shared_ptr<pb::link::MemBus> bus = pb::link::MemBus::create();
  std::unique_ptr<pb::link::Line> line = bus->attach();
  std::unique_ptr<pb::link::Line> slave_line = bus->attach();
  std::unique_ptr<pb::slave::DpSlave> slave;
  EchoModel* model = nullptr;
  fdl::Deframer rx;
  TIME now{0};
  std::uint8_t address = 1;

  explicit RawMaster(const pb::slave::SlaveConfig& c) {
    auto m = std::make_unique<EchoModel>(8);
    model = m.get();
    slave = std::make_unique<pb::slave::DpSlave>(c, std::move(m), *slave_line);
  }
  // Sends `t`, lets the slave answer; the answer (if any).
  std::optional<fdl::Telegram> exchange(const fdl::Telegram& t, TIME dt = 1ms) {
    std::array<std::uint8_t, fdl::kMaxTelegram> b{};
    line->send({b.data(), fdl::encode(t, b)});
    now += dt;
    slave->tick(now);
    std::array<std::uint8_t, 512> in{};
    const std::size_t n = line->receive(in);
    rx.push({in.data(), n});
    fdl::Telegram a;
    if (rx.next(a)) return a;
    return std::nullopt;
  }
  fdl::Telegram srd(std::int16_t dsap, std::span<const std::uint8_t> data = {},
                    std::uint8_t from = 0) {
    return fdl::make_data(slave->address(), from ? from : address,
                          fdl::kFcRequest | fdl::kReqSrdHigh, dsap, dsap < 0 ? -1 : dp::kSapMaster,
                          data);
  }
  dp::Diagnosis diag(std::uint8_t from = 0) {
    const auto a = exchange(srd(dp::kSapSlaveDiag, {}, from));
    EXPECT_TRUE(a.has_value());
    const auto d = a ? dp::Diagnosis::decode(a->du()) : std::nullopt;
    EXPECT_TRUE(d.has_value());
    return d.value_or(dp::Diagnosis{});
  }
  bool set_prm(const dp::SetPrm& p, std::uint8_t from = 0) {
    const auto b = p.encode();
    const auto a = exchange(srd(dp::kSapSetPrm, b, from));
    return a && a->format == fdl::Format::ShortAck;
  }
  bool chk_cfg(std::vector<std::uint8_t> cfg) {
    const auto a = exchange(srd(dp::kSapChkCfg, cfg));
    return a && a->format == fdl::Format::ShortAck;
  }
  std::optional<fdl::Telegram> data_exchange(std::vector<std::uint8_t> out, TIME dt = 1ms) {
    return exchange(srd(-1, out), dt);
  }
  void global_control(std::uint8_t cmd, std::uint8_t groups) {
    const dp::GlobalControl gc{cmd, groups};
    const auto b = gc.encode();
    std::array<std::uint8_t, fdl::kMaxTelegram> buf{};
    const auto t = fdl::make_data(fdl::kBroadcast, address, fdl::kFcRequest | fdl::kReqSdnHigh,
                                  dp::kSapGlobalControl, dp::kSapMaster, b);
    line->send({buf.data(), fdl::encode(t, buf)});
    now += 1ms;
    slave->tick(now);
  }
  // Set_Prm (Lock, WD 100 ms, Freeze/Sync, group 1) + Chk_Cfg B7.
  void start(std::uint8_t status = dp::kPrmLockReq | dp::kPrmWdOn | dp::kPrmFreezeReq |
                                   dp::kPrmSyncReq) {
    dp::SetPrm p;
    p.station_status = status;
    p.wd_fact1 = 10;
    p.wd_fact2 = 1;
    p.ident = 0x5610;
    p.group = 0x01;
    EXPECT_TRUE(set_prm(p));
    EXPECT_TRUE(chk_cfg({0xB7}));
  }
};

}  // namespace pbtest

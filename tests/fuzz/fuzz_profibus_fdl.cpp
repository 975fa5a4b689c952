// Fuzz target: the PROFIBUS FDL decoder and the DP stations behind it
// (iec-io/profibus). The first byte picks the part:
//  0 a byte stream through the deframer: every telegram it yields encodes
//    again, and the encoded bytes decode to the same telegram (property);
//  1 a DP master and a DP slave (the PR1721/31 identity) on an in-memory
//    line, a rogue station sending the input's bytes between their ticks
//    for up to 300 ticks of 1 ms: no crash, and whenever the master does
//    not call the slave on line its inputs are zero (property).
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>

#include "fuzz_input.hpp"
#include "plc/profibus/dp/describe.hpp"
#include "plc/profibus/dp/services.hpp"
#include "plc/profibus/fdl/deframer.hpp"
#include "plc/profibus/link/mem_line.hpp"
#include "plc/profibus/master/dp_master.hpp"
#include "plc/profibus/slave/dp_slave.hpp"

using namespace plc::profibus;
using plc::fuzz::FuzzInput;
using namespace std::chrono_literals;

namespace {

bool same(const fdl::Telegram& a, const fdl::Telegram& b) {
  if (a.format == fdl::Format::ShortAck) return b.format == fdl::Format::ShortAck;
  if (a.format == fdl::Format::Token)
    return b.format == fdl::Format::Token && a.da == b.da && a.sa == b.sa;
  return a.da == b.da && a.sa == b.sa && a.fc == b.fc && a.dsap == b.dsap && a.ssap == b.ssap &&
         a.dseg == b.dseg && a.sseg == b.sseg && a.length == b.length &&
         std::equal(a.data.begin(), a.data.begin() + a.length, b.data.begin());
}

void stream(FuzzInput& in) {
  fdl::Deframer d;
  while (!in.empty()) {
    d.push(in.bytes(1 + in.byte() % 64));
    fdl::Telegram t;
    while (d.next(t)) {
      std::array<std::uint8_t, fdl::kMaxTelegram> out{};
      const std::size_t n = fdl::encode(t, out);
      if (n == 0) std::abort();  // whatever decodes must encode
      fdl::Telegram back;
      const auto r = fdl::decode({out.data(), n}, back);
      if (r.status != fdl::DecodeStatus::Ok || r.consumed != n || !same(t, back)) std::abort();
      (void)dp::describe(t);
    }
  }
}

class Echo final : public plc::io::DeviceModel {
 public:
  std::size_t input_size() const override { return 8; }
  std::size_t output_size() const override { return 8; }
  void step(plc::TIME, plc::TIME, std::span<const std::uint8_t> f,
            std::span<std::uint8_t> t) override {
    for (std::size_t i = 0; i < 8; ++i) t[i] = static_cast<std::uint8_t>(f[i] + 1);
  }
};

void stations(FuzzInput& in) {
  auto bus = link::MemBus::create();
  auto ml = bus->attach(), sl = bus->attach(), rogue = bus->attach();
  master::MasterConfig mc;
  mc.bus = fdl::bus_parameters(1500000, {}, 1, 8);
  mc.cycle = 2ms;
  mc.retry = 20ms;
  master::DpMaster m(mc, ml.get());
  master::SlaveEntry e;
  e.address = 5;
  e.prm.ident = 0x5610;
  e.prm.station_status = dp::kPrmLockReq | dp::kPrmWdOn | dp::kPrmFreezeReq | dp::kPrmSyncReq;
  e.prm.wd_fact1 = 5;
  e.prm.group = 1;
  e.cfg = {0xB7};
  e.input_bytes = e.output_bytes = 8;
  m.add(e);
  slave::SlaveConfig sc;
  sc.address = 5;
  sc.ident = 0x5610;
  sc.input_bytes = sc.output_bytes = 8;
  sc.modules = {0xB7, 0xBF, 0x37, 0x3F, 0xF3, 0xF7, 0xFF, 0x73, 0x77, 0x7F};
  sc.max_modules = 4;
  slave::DpSlave s(sc, std::make_unique<Echo>(), *sl);
  plc::TIME now{0};
  for (int tick = 0; tick < 300 && !in.empty(); ++tick) {
    now += 1ms;
    const std::uint8_t what = in.byte();
    if (what & 1) rogue->send(in.bytes(1 + in.byte() % 32));
    if (what & 2) m.global_control(in.byte(), in.byte());
    for (int i = 0; i < 8; ++i) {
      m.tick(now);
      s.tick(now);
    }
    if (m.state(0) != master::SlaveState::Online)
      for (const std::uint8_t b : m.inputs(0))
        if (b != 0) std::abort();
    (void)m.diagnostics(0);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  switch (in.byte() % 2) {
    case 0:
      stream(in);
      break;
    default:
      stations(in);
      break;
  }
  return 0;
}
